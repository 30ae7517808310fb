"""fmpy's validation of each FMU given on the command line.

`fmpy.validation.validate_fmu` checks the model description against the FMI 2.0 XML
schema, variable names, the ModelStructure, start values, causality/variability
combinations and units. Every FMU must pass with no problem at all.

Usage: python fmpy_validate.py FMU...   (exit status 1 when any FMU has a problem)
"""
import sys

from fmpy.validation import validate_fmu


def main(fmu_paths: list[str]) -> int:
    if not fmu_paths:
        print("no FMU given")
        return 2
    failed = 0
    for path in fmu_paths:
        problems = validate_fmu(path)
        if problems:
            failed += 1
            print(f"FAILED {path}: {len(problems)} problem(s)")
            for problem in problems:
                print(f"  - {problem}")
        else:
            print(f"ok     {path}")
    print(f"fmpy_validate: {len(fmu_paths) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
