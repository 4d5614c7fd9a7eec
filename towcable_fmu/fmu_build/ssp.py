"""The SSP file (SSP 1.0: ``SystemStructure.ssd`` in a zip) of the three-FMU system.

Everything comes from the contract: the components and their order (``[system]``), the
connectors of each component (its inputs and outputs; diagnostics such as
``model_wall_time`` left out), their types and units, the connections (one per signal),
and the unit definitions. Parameter values (e.g. the ones a ``towcable cosim`` run used)
are written as inline parameter bindings, in one parameter set named
:data:`PARAMETER_SET` across the components; the FMUs are stored under ``resources/``.

Tested with libcosim (``libcosimpy``), the OSP's ``ecos`` and ``fmpy.ssp``; see the
README for what ``fmpy.ssp`` cannot do.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path
from typing import Any, Mapping

from ..common import contract

#: Name of the parameter set of every component: tools that apply sets by name (the OSP's
#: ``ecos simulate --parameterSet case``) apply the whole case at once.
PARAMETER_SET = "case"
NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
      "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
      "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues"}
for _prefix, _uri in NS.items():
    ET.register_namespace(_prefix, _uri)


def _q(tag: str) -> str:
    prefix, name = tag.split(":")
    return f"{{{NS[prefix]}}}{name}"


def _value_text(kind: str, value: Any) -> str:
    if kind == "Real":
        return repr(float(value))
    if kind == "Boolean":
        return "true" if value else "false"
    if kind == "Integer":
        return str(int(value))
    return str(value)


def system_structure(parameters: Mapping[str, Mapping[str, Any]] | None = None, start_time: float = 0.0,
                     stop_time: float | None = None) -> bytes:
    """``SystemStructure.ssd`` of the system (bytes, UTF-8).

    Parameters
    ----------
    parameters
        FMU name -> parameter name -> value, written as parameter bindings.
    start_time, stop_time
        DefaultExperiment of the system.
    """
    parameters = parameters or {}
    sysinfo = contract.system()
    specs = contract.fmus()
    root = ET.Element(_q("ssd:SystemStructureDescription"), version="1.0", name=sysinfo["name"])
    system = ET.SubElement(root, _q("ssd:System"), name=sysinfo["name"], description=sysinfo["description"])
    elements = ET.SubElement(system, _q("ssd:Elements"))
    used_units: list[str] = []
    for name in sysinfo["components"]:
        spec = specs[name]
        comp = ET.SubElement(elements, _q("ssd:Component"), name=name, type="application/x-fmu-sharedlibrary",
                             source=f"resources/{name}.fmu", description=spec.description)
        connectors = ET.SubElement(comp, _q("ssd:Connectors"))
        for var in spec.inputs + spec.outputs:
            if var.diagnostic:
                continue
            con = ET.SubElement(connectors, _q("ssd:Connector"), name=var.name, kind=var.causality,
                                description=var.description)
            attrs = {"unit": var.unit} if var.type == "Real" else {}
            ET.SubElement(con, _q(f"ssc:{var.type}"), attrs)
            if var.type == "Real" and var.unit not in used_units:
                used_units.append(var.unit)
        values = parameters.get(name, {})
        if values:
            bindings = ET.SubElement(comp, _q("ssd:ParameterBindings"))
            binding = ET.SubElement(bindings, _q("ssd:ParameterBinding"))
            pvalues = ET.SubElement(binding, _q("ssd:ParameterValues"))
            pset = ET.SubElement(pvalues, _q("ssv:ParameterSet"), version="1.0", name=PARAMETER_SET)
            plist = ET.SubElement(pset, _q("ssv:Parameters"))
            for pname, value in values.items():
                var = spec.variable(pname)
                par = ET.SubElement(plist, _q("ssv:Parameter"), name=pname)
                attrs = {"value": _value_text(var.type, value)}
                if var.type == "Real":
                    attrs["unit"] = var.unit
                    if var.unit not in used_units:
                        used_units.append(var.unit)
                ET.SubElement(par, _q(f"ssv:{var.type}"), attrs)
    connections = ET.SubElement(system, _q("ssd:Connections"))
    for c in contract.connections():
        ET.SubElement(connections, _q("ssd:Connection"), startElement=c.source, startConnector=c.signal,
                      endElement=c.target, endConnector=c.signal)
    units = ET.SubElement(root, _q("ssd:Units"))
    table = contract.units()
    for uname in used_units:
        unit = ET.SubElement(units, _q("ssc:Unit"), name=uname)
        exps = table[uname]
        base = {k: str(int(v)) for k, v in exps.items() if k in contract.BASE_UNITS and v}
        for key in ("factor", "offset"):
            if key in exps:
                base[key] = repr(float(exps[key]))
        ET.SubElement(unit, _q("ssc:BaseUnit"), base)
    experiment = {"startTime": repr(float(start_time))}
    if stop_time is not None:
        experiment["stopTime"] = repr(float(stop_time))
    ET.SubElement(root, _q("ssd:DefaultExperiment"), experiment)
    ET.indent(root)
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8")


def write_ssp(path: str | Path, fmus: Mapping[str, str | Path],
              parameters: Mapping[str, Mapping[str, Any]] | None = None, start_time: float = 0.0,
              stop_time: float | None = None) -> Path:
    """Write the SSP file: ``SystemStructure.ssd`` and the FMUs under ``resources/``.

    Parameters
    ----------
    path
        The ``.ssp`` file to write.
    fmus
        FMU name -> ``.fmu`` file (the three FMUs of the contract).
    parameters, start_time, stop_time
        See :func:`system_structure`.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", system_structure(parameters, start_time, stop_time))
        for name in contract.system()["components"]:
            z.write(fmus[name], f"resources/{name}.fmu")
    return path
