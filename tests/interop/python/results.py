"""CSV results as the harness writes them (harness/src/results.rs): a header
`time,instance.variable,...` and one row per communication point. Python's repr of a float
is the shortest string that reads back to the same double, as the harness's ryu output, so
a comparison of the two files is bit-exact."""


def write_csv(path: str, names: list[str], times: list[float], rows: list[list[float]]) -> None:
    with open(path, "w") as f:
        f.write(",".join(["time", *names]) + "\n")
        for time, row in zip(times, rows):
            f.write(",".join(repr(float(x)) for x in [time, *row]) + "\n")
