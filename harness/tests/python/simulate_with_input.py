"""fmpy's simulate_fmu over an FMU's DefaultExperiment with inputs from a CSV table (a
`time` column, one column per input), writing every output to a CSV: the run the harness's
`run X.fmu --input FILE.csv` is compared with."""
import sys

import numpy as np
from fmpy import read_model_description, simulate_fmu
from fmpy.util import read_csv, write_csv

fmu, table, out = sys.argv[1:4]
description = read_model_description(fmu)
outputs = [v.name for v in description.modelVariables if v.causality == "output"]
result = simulate_fmu(
    fmu,
    fmi_type="CoSimulation",
    input=read_csv(table),
    output=outputs,
    output_interval=float(description.defaultExperiment.stepSize),
)
write_csv(out, result)
print(len(result), "rows")
