"""Reads one harness run written twice, as CSV and as an Arrow IPC file, with pandas
(read_feather), polars (read_ipc) and pyarrow, and checks that every value of every column
equals the CSV's bit for bit. The CSV is parsed with Python's float(), which rounds
correctly, so it is the reference. Usage: read_results.py RUN.csv RUN.arrow"""
import csv
import struct
import sys

import pandas as pd
import polars as pl
import pyarrow.feather as feather


def bits(values):
    return [struct.unpack("<Q", struct.pack("<d", float(v)))[0] for v in values]


def main(csv_path: str, arrow_path: str) -> None:
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    columns = {name: bits(row[j] for row in rows[1:]) for j, name in enumerate(names)}
    assert len(rows) > 1, "the CSV holds no rows"

    readers = {
        "pandas.read_feather": lambda: pd.read_feather(arrow_path),
        "polars.read_ipc": lambda: pl.read_ipc(arrow_path),
        "pyarrow.feather.read_table": lambda: feather.read_table(arrow_path),
    }
    for reader, read in readers.items():
        table = read()
        got = list(table.columns) if reader != "pyarrow.feather.read_table" else table.column_names
        assert got == names, f"{reader}: columns {got[:5]}... differ from the CSV's {names[:5]}..."
        for name in names:
            if reader == "pyarrow.feather.read_table":
                values = table.column(name).to_pylist()
            else:
                values = table[name].to_list()
            assert bits(values) == columns[name], f"{reader}: column {name} differs from the CSV"
        print(f"{reader}: {len(names)} columns x {len(rows) - 1} rows equal to the CSV bit for bit")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
