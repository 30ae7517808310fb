"""Each FMI 3.0 FMU's terminalsAndIcons/terminalsAndIcons.xml against the FMI 3.0 XSD that
fmpy ships (fmpy/schema/fmi3/fmi3TerminalsAndIcons.xsd, validated by lxml), its member
variables against the FMU's own modelDescription.xml, and its icon as a PNG.

Prints one JSON line per FMU: the terminals with their members (memberName -> variableName,
with the variable's causality) and any problem found; the Rust test
(tests/interop/tests/terminals.rs) judges them.

Usage: python terminals_check.py FMU...
"""
import json
import os
import sys
import zipfile

import fmpy
from lxml import etree

SCHEMA = etree.XMLSchema(etree.parse(os.path.join(
    os.path.dirname(fmpy.__file__), "schema", "fmi3", "fmi3TerminalsAndIcons.xsd")))
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def check(path):
    problems = []
    with zipfile.ZipFile(path) as fmu:
        names = fmu.namelist()
        if "terminalsAndIcons/terminalsAndIcons.xml" not in names:
            return {"fmu": path, "problems": ["no terminalsAndIcons/terminalsAndIcons.xml"],
                    "terminals": {}}
        document = etree.fromstring(fmu.read("terminalsAndIcons/terminalsAndIcons.xml"))
        if not SCHEMA.validate(document):
            problems += [f"XSD: {e.message} (line {e.line})" for e in SCHEMA.error_log]
        description = etree.fromstring(fmu.read("modelDescription.xml"))
        causality = {v.get("name"): v.get("causality", "local")
                     for v in description.find("ModelVariables")}
        has_icon = "terminalsAndIcons/icon.png" in names
        if has_icon and not fmu.read("terminalsAndIcons/icon.png").startswith(PNG_MAGIC):
            problems.append("terminalsAndIcons/icon.png is not a PNG")
    terminals = {}
    for terminal in document.iter("Terminal"):
        members = {}
        for member in terminal.findall("TerminalMemberVariable"):
            variable = member.get("variableName")
            if variable not in causality:
                problems.append(f"terminal {terminal.get('name')}: {variable} is not a "
                                "variable of the model description")
            members[member.get("memberName")] = [variable, causality.get(variable)]
        terminals[terminal.get("name")] = {"matchingRule": terminal.get("matchingRule"),
                                           "terminalKind": terminal.get("terminalKind"),
                                           "members": members}
    return {"fmu": os.path.basename(path), "problems": problems, "terminals": terminals,
            "icon": has_icon}


def main(paths):
    for path in paths:
        print(json.dumps(check(path)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
