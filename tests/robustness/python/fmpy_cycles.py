"""Instantiate / initialize / step / free cycles of a packaged FMU through fmpy's FMU2Slave,
watching the process's resident memory: an FMU that leaks per instance shows up as RSS growing
with the cycles. Usage: python fmpy_cycles.py FMU CYCLES [WARM_UP]. Prints one JSON object."""
import json
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave


def rss_kib() -> int:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS in /proc/self/status")


def main(fmu_path: str, cycles: str, warm_up: str = "") -> int:
    cycles = int(cycles)
    description = read_model_description(fmu_path)
    unzip_dir = extract(fmu_path)
    samples = {}
    # fmpy and the interpreter fill their caches over the first ~1,000 cycles.
    warm_up = int(warm_up) if warm_up else max(1, cycles // 10)
    for k in range(1, cycles + 1):
        # A new FMU2Slave per cycle: fmpy's freeInstance also unloads the library, so this is
        # load, instantiate, initialize, step, terminate, free, unload, as an fmpy user runs it.
        slave = FMU2Slave(
            guid=description.guid,
            unzipDirectory=unzip_dir,
            modelIdentifier=description.coSimulation.modelIdentifier,
            instanceName="cycle",
        )
        slave.instantiate()
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.01)
        slave.terminate()
        slave.freeInstance()
        if k == warm_up or k == cycles:
            samples[k] = rss_kib()
    shutil.rmtree(unzip_dir, ignore_errors=True)
    print(json.dumps({"cycles": cycles, "warm_up": warm_up, "rss_kib": samples}))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
