"""The SSP 2.0 package checked by tools we did not write: its SystemStructure.ssd validated
with lxml against the SSP 2.0 XSDs pyssp-standard ships (the SSD schema, XSD 1.0, skips the
inline ssv:ParameterSet it only admits laxly, so each parameter set is validated against the
SSV 2.0 schema on its own), then read by pyssp-standard's SSD reader, whose compliance check
validates the file again with xmlschema against the XSD 1.1 variant of the SSD schema.
Prints what was read, one fact a line, for the Rust test to compare with the harness's system;
exits 1 naming the first violation.

Usage: python ssp2_validate.py LanderDescent.ssp|SystemStructure.ssd
"""
import pathlib
import sys
import tempfile
import zipfile

import pyssp_standard
from lxml import etree
from pyssp_standard.ssd import SSD

SCHEMAS = pathlib.Path(pyssp_standard.__file__).parent / "resources" / "ssp2"
NS = {
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
}


def schema(name: str) -> etree.XMLSchema:
    return etree.XMLSchema(etree.parse(str(SCHEMAS / name)))


def invalid(what: str, log) -> int:
    print(f"invalid {what}:", file=sys.stderr)
    for error in log:
        print(f"  line {error.line}: {error.message}", file=sys.stderr)
    return 1


def main(path: str) -> int:
    with tempfile.TemporaryDirectory() as scratch:
        if path.endswith(".ssp"):
            with zipfile.ZipFile(path) as archive:
                names = set(archive.namelist())
                ssd_path = pathlib.Path(scratch) / "SystemStructure.ssd"
                ssd_path.write_bytes(archive.read("SystemStructure.ssd"))
        else:
            names = None
            ssd_path = pathlib.Path(path)
        document = etree.parse(str(ssd_path))
        ssd_schema = schema("SystemStructureDescription.xsd")
        if not ssd_schema.validate(document):
            return invalid(f"{path}: SystemStructure.ssd against SSP 2.0 SystemStructureDescription.xsd",
                           ssd_schema.error_log)
        ssv_schema = schema("SystemStructureParameterValues.xsd")
        sets = document.findall(".//ssv:ParameterSet", NS)
        for parameter_set in sets:
            alone = etree.ElementTree(etree.fromstring(etree.tostring(parameter_set)))
            if not ssv_schema.validate(alone):
                return invalid(f"{path}: ssv:ParameterSet (line {parameter_set.sourceline}) against "
                               "SSP 2.0 SystemStructureParameterValues.xsd", ssv_schema.error_log)
        print(f"validated ssd and {len(sets)} parameter sets")

        with SSD(ssd_path) as ssd:
            try:
                ssd.__check_compliance__()
            except Exception as error:  # xmlschema's validation errors
                print(f"invalid {path}: pyssp-standard compliance: {error}", file=sys.stderr)
                return 1
            print(f"system {ssd.name} version {ssd.version}")
            for component in ssd.system.elements:
                if names is not None:
                    assert component.source in names, f"{component.source} is not in the package"
                print(f"component {component.name} {component.component_type} {component.source}")
                for connector in component.connectors:
                    print(f"connector {component.name}.{connector.name} {connector.kind}")
                for binding in component.parameter_bindings or []:
                    print(f"parameter set {component.name} {binding.ssv.name} {binding.ssv.version} "
                          f"{len(binding.ssv.parameters)}")
            for connection in ssd.connections():
                print(f"connection {connection.start_element}.{connection.start_connector} -> "
                      f"{connection.end_element}.{connection.end_connector}")

    # What pyssp-standard 0.9.1 does not keep (FMI 3.0 connector types, dimensions, values),
    # from the validated XML.
    for component in document.iterfind(".//ssd:Component", NS):
        name = component.get("name")
        for connector in component.iterfind("ssd:Connectors/ssd:Connector", NS):
            kind = etree.QName(connector[0]).localname
            sizes = [d.get("size") for d in connector.iterfind("ssc:Dimension", NS)]
            print(f"typed {name}.{connector.get('name')} {kind} [{' '.join(sizes)}]")
        for parameter in component.iterfind(".//ssv:Parameter", NS):
            value = parameter[0]
            sizes = [d.get("size") for d in parameter.iterfind("ssc:Dimension", NS)]
            print(f"value {name}.{parameter.get('name')} {etree.QName(value).localname} "
                  f"[{' '.join(sizes)}] {value.get('value')}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
