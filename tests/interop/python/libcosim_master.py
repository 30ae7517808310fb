"""The closed loop in libcosim (the Open Simulation Platform's co-simulation library, through
its Python wrapper libcosimpy), built two ways:

- `api SYSTEM.json OUT.csv`: an execution with a fixed step, each instance added as a local
  slave, parameters given as initial values and every scalar connection made with
  `connect_real_variables` / `connect_integer_variables` (value references looked up by name
  in the FMU's model description);
- `ssp SSP_DIR OUT.csv`: the execution libcosim builds itself from the unpacked SSP's
  SystemStructure.ssd (components, connections, inline parameter bindings), at the same step.

libcosim ignores FMI 2.0 Enumeration variables: LanderGnc's `control_law` keeps its start
value (2, decoupled, the paper scenario's value) in both modes.

libcosim's fixed-step algorithm (src/cosim/algorithm/fixed_step_algorithm.cpp) is Jacobi:
all slaves step from t_k (each first setting its inputs from values transferred after the
previous step), then every output is transferred to the inputs it feeds. Initialization
runs as many set-inputs/read-outputs iterations in initialization mode as there are slaves,
so the controller's first command answers the plant's initial state. Time is integer
nanoseconds: the FMUs see t_k = k h_ns / 1e9 and h_k = t_{k+1} - t_k.

Every output of every slave is recorded after each step, as `instance.variable`, under the
execution's time after the step.

Usage: python libcosim_master.py api SYSTEM.json OUT.csv
       python libcosim_master.py ssp SSP_DIR OUT.csv STOP_TIME STEP_SIZE
"""
import json
import sys

from fmpy import read_model_description
from libcosimpy.CosimEnums import CosimVariableCausality, CosimVariableType
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

from results import write_csv


def nanoseconds(seconds: float) -> int:
    return int(round(seconds * 1e9))


def check(ok: bool, what: str) -> None:
    if not ok:
        raise RuntimeError(f"libcosim refused: {what}")


def from_api(system: dict, step_ns: int) -> CosimExecution:
    execution = CosimExecution.from_step_size(step_ns)
    index, variables = {}, {}
    for instance in system["instances"]:
        slave = CosimLocalSlave(fmu_path=instance["fmu"], instance_name=instance["name"])
        index[instance["name"]] = execution.add_local_slave(slave)
        description = read_model_description(instance["fmu"])
        variables[instance["name"]] = {v.name: v for v in description.modelVariables}
        for name, value in instance["parameters"]:
            v = variables[instance["name"]][name]
            if v.type == "Enumeration":
                # libcosim 0.x ignores FMI 2.0 Enumeration variables ("variable type not
                # supported, variable ... will be ignored"): it can neither set nor connect
                # them. A value equal to the start value needs no setting; another cannot be
                # flown here, and is refused rather than silently dropped.
                if int(value) != int(v.start):
                    raise RuntimeError(f"libcosim cannot set Enumeration {instance['name']}.{name} "
                                       f"to {value} (start {v.start})")
                print(f"libcosim api: {instance['name']}.{name} = {value} is the start value "
                      f"(libcosim ignores Enumeration variables)")
                continue
            if v.type == "Real":
                ok = execution.real_initial_value(index[instance["name"]], v.valueReference, float(value))
            elif v.type in ("Integer", "Enumeration"):
                ok = execution.integer_initial_value(index[instance["name"]], v.valueReference, int(value))
            else:
                ok = execution.boolean_initial_value(index[instance["name"]], v.valueReference, bool(value))
            check(ok, f"initial value {instance['name']}.{name} = {value}")
    for source, destination in system["connections"]:
        (a, a_var), (b, b_var) = source.split(".", 1), destination.split(".", 1)
        out, inp = variables[a][a_var], variables[b][b_var]
        connect = (execution.connect_real_variables if out.type == "Real"
                   else execution.connect_integer_variables)
        # The wrapper returns libcosim's C status here: 0 is success.
        check(connect(index[a], out.valueReference, index[b], inp.valueReference) == 0,
              f"connection {source} -> {destination}")
    return execution


def record_outputs(execution: CosimExecution, steps: int) -> tuple[list[str], list[float], list[list[float]]]:
    observer = CosimObserver.create_last_value()
    check(execution.add_observer(observer), "last-value observer")
    columns = []  # (slave index, type, reference, name)
    for info in execution.slave_infos():
        for v in execution.slave_variables(info.index):
            if CosimVariableCausality(v.causality) == CosimVariableCausality.OUTPUT:
                columns.append((info.index, CosimVariableType(v.type), v.reference,
                                f"{info.name.decode()}.{v.name.decode()}"))
    times, rows = [], []
    for _ in range(steps):
        check(execution.step(), f"step at t = {execution.status().current_time} ns")
        times.append(execution.status().current_time / 1e9)
        row = []
        for slave, kind, reference, _ in columns:
            if kind == CosimVariableType.REAL:
                row.append(observer.last_real_values(slave, [reference])[0])
            elif kind == CosimVariableType.INTEGER:
                row.append(float(observer.last_integer_values(slave, [reference])[0]))
            else:
                row.append(float(observer.last_boolean_values(slave, [reference])[0]))
        rows.append(row)
    return [name for *_, name in columns], times, rows


def main(mode: str, source: str, out_path: str, *times: str) -> int:
    log_output_level(CosimLogLevel.WARNING)
    if mode == "api":
        with open(source) as f:
            system = json.load(f)
        start, stop, step = system["start_time"], system["stop_time"], system["step_size"]
        assert start == 0.0, "libcosim executions start at t = 0"
        execution = from_api(system, nanoseconds(step))
    else:
        stop, step = float(times[0]), float(times[1])
        execution = CosimExecution.from_ssp_file(source, nanoseconds(step))
    steps = nanoseconds(stop) // nanoseconds(step)
    names, times_s, rows = record_outputs(execution, steps)
    write_csv(out_path, names, times_s, rows)
    print(f"libcosim {mode}: {execution.num_slaves()} slaves, {len(times_s)} steps, "
          f"{len(names)} outputs, last t = {times_s[-1]!r} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
