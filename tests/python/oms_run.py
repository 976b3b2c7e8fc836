"""Run FMUs in OMSimulator 3 (a subprocess of test_omsimulator.py: the library keeps global state
and a crash must not take pytest down).

argv[1] is a JSON spec: {"components": {name: {"fmu": path, "params": {var: value}}},
"connections": [["truth.meas_epoch", "filter.meas_epoch"], ...], "step": h, "stop": T,
"observe": {name: [var, ...]}, "result": csv path}, or, for an SSP package, {"ssp": path,
"system": name, "inputs": {connector: [[t_from, value], ...]}, "params": {"comp.var": value},
...}: the system's input
connectors follow the piecewise-constant schedules (the value of the last t_from <= the step's
start holds over the step). The system is stepped one communication step
at a time with stepUntil; after initialisation and after every step the observed variables are read
through the C API (exact doubles, unlike the result file's 12 digits). Prints one JSON line:
{"times": [...], "series": {name: [[value per variable] per point]}}."""

import json
import sys

from OMSimulator import SSP, CRef
from OMSimulator import capi as _capi


def _set_string(self, cref, value):
    # OMSimulator 3.0.0.post114's wrapper passes the str to a c_char_p argument (ctypes refuses
    # it); encode it as the C API expects.
    return _capi.Status(self.obj.oms_setString(cref.encode(), value.encode()))


_capi.capi.setString = _set_string


def main():
    spec = json.loads(sys.argv[1])
    root = spec.get("system", "default")
    model = SSP(spec["ssp"]) if "ssp" in spec else SSP()
    for name, c in spec.get("components", {}).items():
        model.addResource(c["fmu"], new_name=f"resources/{name}.fmu")
        model.addComponent(CRef("default", name), f"resources/{name}.fmu")
        for var, value in c.get("params", {}).items():
            model.setValue(CRef("default", name, var), value)
    for a, b in spec.get("connections", []):
        model.addConnection(CRef("default", *a.split(".", 1)), CRef("default", *b.split(".", 1)))
    inst = model.instantiate()
    # OMSimulator 3.0.0.post114 does not apply an SSP's .ssv String parameters (after instantiate
    # `truth.scenario` still reads the FMU's default): "params" sets component parameters
    # through the API, {"component.variable": value}, before initialisation.
    for name, value in spec.get("params", {}).items():
        inst.setValue(CRef(root, *name.split(".", 1)), value)
    inst.setResultFile(spec["result"])
    inst.setStopTime(spec["stop"])
    inst.setFixedStepSize(spec["step"])
    inst.initialize()
    observe = spec["observe"]
    series = {name: [] for name in observe}
    times = []

    def grab(t):
        times.append(t)
        for name, names in observe.items():
            series[name].append([inst.getValue(CRef(root, name, v)) for v in names])

    def apply_inputs(t):
        for connector, schedule in spec.get("inputs", {}).items():
            value = [v for t_from, v in schedule if t_from <= t + 1e-9][-1]
            inst.setValue(CRef(root, connector), value)

    grab(0.0)
    n = round(spec["stop"] / spec["step"])
    for k in range(1, n + 1):
        t = k * spec["step"]
        apply_inputs(t - spec["step"])
        inst.stepUntil(t)
        grab(t)
    inst.terminate()
    inst.delete()
    print(json.dumps({"times": times, "series": series}))


if __name__ == "__main__":
    main()
