"""Two independent checkers on each FMU given: fmpy's `validate_fmu` (schema, names,
ModelStructure, start values, causality/variability) and fmutool's `-check`
(fmu-manipulation-toolbox: generic conformity against the FMI 2.0 schema, then semantic
checks). Any problem, error or warning fails; so does a missing "all good" line, so that a
fmutool that silently stopped checking cannot pass.

Usage: python checkers.py FMU...   (exit status 1 when any check fails)
"""
import os
import subprocess
import sys

from fmpy.validation import validate_fmu

FMUTOOL = os.path.join(os.path.dirname(sys.executable), "fmutool")
# What fmutool 2.0 prints when a check passes; both must be there.
FMUTOOL_PASSES = ("This FMU seems to be compliant with FMI-2.0.",
                  "No semantic error against the FMI-2 standard.")


def fmutool_check(path: str) -> list[str]:
    run = subprocess.run([FMUTOOL, "-input", path, "-check"], capture_output=True, text=True)
    output = run.stdout + run.stderr
    problems = [line.strip() for line in output.splitlines()
                if line.startswith(("WARNING", "ERROR", "CRITICAL"))]
    if run.returncode != 0:
        problems.append(f"fmutool exited with {run.returncode}")
    problems += [f"fmutool did not report: {line}" for line in FMUTOOL_PASSES if line not in output]
    for line in output.splitlines():
        print(f"    fmutool | {line}")
    return problems


def main(paths: list[str]) -> int:
    failed = 0
    for path in paths:
        problems = [f"fmpy: {p}" for p in validate_fmu(path)] + fmutool_check(path)
        name = os.path.basename(path)
        if problems:
            failed += 1
            print(f"FAILED {name}:")
            for problem in problems:
                print(f"  - {problem}")
        else:
            print(f"ok     {name}: fmpy validate and fmutool -check found no error and no warning")
    print(f"checkers: {len(paths) - failed} passed, {failed} failed")
    return 1 if failed or not paths else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
