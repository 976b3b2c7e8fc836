"""Our FMI 3.0 co-simulation FMUs with their arrays (`entrynav fmu pack --fmi 3 --arrays`) in tools
we did not write (the default pack, scalars only, runs alone in every tool: test_fmu_alone.py):

- fmpy validates each description (schema and rules) without a problem;
- fmpy simulates each FMI 3.0 FMU with every scalar output bitwise equal to the same FMU packed
  as FMI 2.0 (same seed, dispersions, inputs);
- the arrays (`est_x`, `est_sigma`, `est_covariance`, sized by the structural parameter
  `n_state_slots`) hold exactly the scalar outputs, and the covariance's diagonal is σ²;
- an FMU state saved, serialized and restored through fmpy's FMI 3.0 API replays the run bit for
  bit;
- the Reference-FMUs `fmusim` (FMI 3.0 importer, ../shared/tools) simulates each FMI 3.0 FMU
  equal to the library to the 16 digits it writes, the truth also with a 2 s step.
"""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi3 import FMU3Slave
from fmpy import extract
from fmpy.validation import validate_fmu

import test_fmusim
from conftest import ENTRYNAV, ENTRYNAV_DEV, FMU_DIR, MODELS, run

PARAMS = {"seed": 4, "dispersed": True}
ARRAYS_DIR = FMU_DIR / "fmi3-arrays"


@pytest.fixture(scope="session")
def fmus3(fmus):
    """Paths of the three FMI 3.0 .fmu files with arrays (in fmi3-arrays/ beside the FMI 2.0 ones)."""
    paths = {m: ARRAYS_DIR / f"{m}-fmi3.fmu" for m in MODELS}
    if not all(p.exists() for p in paths.values()):
        r = run([ENTRYNAV, "fmu", "pack", "--fmi", "3", "--arrays", "--out", ARRAYS_DIR])
        assert r.returncode == 0, r.stderr
    return paths


@pytest.mark.parametrize("model", MODELS)
def test_fmpy_validates_the_fmi3_description(fmus3, model):
    assert validate_fmu(str(fmus3[model])) == []
    md = read_model_description(str(fmus3[model]))
    assert md.fmiVersion == "3.0"
    assert md.coSimulation.modelIdentifier == model


def _bits(a):
    a = np.ascontiguousarray(a)
    return a.view(np.uint64) if a.dtype == np.float64 else a.astype(np.int64)


@pytest.mark.parametrize("model", MODELS)
def test_fmpy_fmi3_outputs_equal_fmi2_bitwise(fmus, fmus3, model):
    md2 = read_model_description(str(fmus[model]))
    outs = [v.name for v in md2.modelVariables if v.causality == "output"]
    params = {} if model == "MarsEntryNavFilter" else PARAMS
    kw = dict(output_interval=1.0, start_values=params, output=outs)
    r2 = simulate_fmu(str(fmus[model]), **kw)
    r3 = simulate_fmu(str(fmus3[model]), **kw)
    assert len(r3) == len(r2) and len(r2) > 100
    assert np.array_equal(r2["time"], r3["time"])
    differ = [n for n in outs if not np.array_equal(_bits(r2[n]), _bits(r3[n]))]
    assert differ == [], f"{model}: outputs that differ between FMI 3.0 and 2.0: {differ}"
    print(f"{model}: {len(outs)} outputs x {len(r2)} rows bitwise equal")


def test_fmi3_arrays_hold_the_scalars(fmus3):
    md = read_model_description(str(fmus3["MarsEntryNav"]))
    slots = next(v for v in md.modelVariables if v.name == "n_state_slots")
    assert slots.causality == "structuralParameter" and int(slots.start) == 12
    est = next(v for v in md.modelVariables if v.name == "est_covariance")
    assert [d.valueReference for d in est.dimensions] == [slots.valueReference] * 2
    scalars = [f"est_x_{i}" for i in range(1, 13)] + [f"est_sigma_{i}" for i in range(1, 13)]
    r = simulate_fmu(
        str(fmus3["MarsEntryNav"]),
        stop_time=120.0,
        output_interval=1.0,
        start_values=PARAMS,
        output=["est_x", "est_sigma", "est_covariance", "n_states", *scalars],
    )
    n = int(r["n_states"][-1])
    assert 0 < n <= 12
    for i in range(12):
        assert np.array_equal(_bits(r["est_x"][:, i]), _bits(r[f"est_x_{i + 1}"]))
        assert np.array_equal(_bits(r["est_sigma"][:, i]), _bits(r[f"est_sigma_{i + 1}"]))
    cov = r["est_covariance"]
    assert cov.shape == (len(r), 12, 12)
    np.testing.assert_allclose(
        np.sqrt(np.einsum("kii->ki", cov)), r["est_sigma"], rtol=1e-12, atol=0
    )
    assert np.array_equal(cov, np.transpose(cov, (0, 2, 1)))
    assert np.all(cov[:, n:, :] == 0) and np.all(cov[:, :, n:] == 0)
    assert np.all(np.linalg.eigvalsh(cov[-1][:n, :n]) > 0)


def test_fmi3_state_round_trip_through_fmpy(fmus3, tmp_path):
    fmu = str(fmus3["MarsEntryNav"])
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(fmu, str(tmp_path / "u")),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="roundtrip",
    )
    slave.instantiate()
    slave.setInt32([vr["seed"]], [4])
    slave.setBoolean([vr["dispersed"]], [True])
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    watch = [vr["est_x_1"], vr["est_x_4"], vr["truth_r"], vr["nis"]]
    t = 0.0
    while t < 50.0:
        slave.doStep(t, 1.0)
        t += 1.0
    state = slave.getFMUState()
    blob = slave.serializeFMUState(state)
    first = []
    for k in range(50):
        slave.doStep(t + k, 1.0)
        first.append(slave.getFloat64(watch))
    restored = slave.deserializeFMUState(blob)
    slave.setFMUState(restored)
    again = []
    for k in range(50):
        slave.doStep(t + k, 1.0)
        again.append(slave.getFloat64(watch))
    assert np.array_equal(_bits(np.array(first)), _bits(np.array(again)))
    slave.freeFMUState(state)
    slave.freeFMUState(restored)
    slave.terminate()
    slave.freeInstance()


FMUSIM_PARAMS = {"seed": "4", "dispersed": "true"}


@pytest.mark.skipif(test_fmusim.REASON is not None, reason=f"fmusim unavailable: {test_fmusim.REASON}")
@pytest.mark.parametrize(
    "model,params",
    [
        ("MarsEntryNav", dict(FMUSIM_PARAMS, filter="dcifaif")),
        ("MarsEntryNavFilter", dict(FMUSIM_PARAMS, filter="dcifaif")),
        ("MarsEntryTruth", FMUSIM_PARAMS),
    ],
)
def test_fmusim_runs_the_fmi3_fmus_equal_to_the_library(fmus3, model, params, tmp_path):
    header, rows, _ = test_fmusim.fmusim(fmus3[model], params, 1, 300, tmp_path)
    ref = test_fmusim.reference(model, params, 1, 300, tmp_path)
    n = test_fmusim.compare(header, rows, ref, f"{model} (FMI 3.0)")
    assert n >= 20 * len(rows)
    print(f"{model} FMI 3.0 in fmusim: {len(rows)} rows, {n} values equal to 16 digits")


@pytest.mark.skipif(test_fmusim.REASON is not None, reason=f"fmusim unavailable: {test_fmusim.REASON}")
def test_fmusim_runs_the_fmi3_truth_with_a_2_s_step(fmus3, tmp_path):
    header, rows, _ = test_fmusim.fmusim(fmus3["MarsEntryTruth"], FMUSIM_PARAMS, 2, 300, tmp_path)
    assert float(rows[-1][0]) == 300.0
    ref = test_fmusim.reference("MarsEntryTruth", FMUSIM_PARAMS, 2, 300, tmp_path)
    test_fmusim.compare(header, rows, ref, "truth FMI 3.0, 2 s")


def test_fmi3_cross_check_files_pass_fmpy(fmus3, tmp_path):
    """The FMI Cross-Check files of the FMI 3.0 FMUs (fmus/3.0/cs/x86_64-linux/…): fmpy's
    repository validator (with the FMI 3.0 schema) finds no problem, and fmpy's FMI 3.0 master fed
    with each `_in.csv` reproduces each `_ref.csv` bit for bit."""
    from fmpy.cross_check.validate_vendor_repo import read_csv, validate_repo
    from fmpy.util import read_ref_opt_file

    out = tmp_path / "xc3"
    r = run([ENTRYNAV_DEV, "fmu", "cross-check", "--out", out, *fmus3.values()], timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    n_fmus, _, problems = validate_repo(str(out))
    assert n_fmus == 3 and problems == [], problems
    dirs = sorted(out.glob("fmus/3.0/cs/x86_64-linux/entrynav/*/*"))
    assert [d.name for d in dirs] == sorted(MODELS)
    for model_dir in dirs:
        name = model_dir.name
        opt = read_ref_opt_file(str(model_dir / f"{name}_ref.opt"))
        ref = read_csv(str(model_dir / f"{name}_ref.csv"))
        inputs = read_csv(str(model_dir / f"{name}_in.csv"))
        res = simulate_fmu(str(model_dir / f"{name}.fmu"), start_time=opt["StartTime"], stop_time=opt["StopTime"],
                           output_interval=opt["StepSize"], input=inputs, output=list(ref.dtype.names[1:]))
        for col in ref.dtype.names[1:]:
            assert np.array_equal(np.asarray(res[col], dtype=np.float64), ref[col]), f"{name}: {col} differs"
        print(name, "FMI 3.0 cross-check:", len(ref), "rows", ref.dtype.names[1:])


def _oms_available():
    try:
        import OMSimulator  # noqa: F401

        return True
    except ImportError:
        return False


@pytest.mark.skipif(not _oms_available(), reason="OMSimulator is not installed (scripts/setup.sh installs the wheel)")
def test_omsimulator_runs_the_fmi3_truth_with_a_2_s_step_equal_to_the_library(fmus3, tmp_path):
    import test_omsimulator as t

    names = t.TRUTH
    spec = {
        "components": {"truth": {"fmu": str(fmus3["MarsEntryTruth"]), "params": PARAMS}},
        "step": 2.0,
        "stop": 300.0,
        "observe": {"truth": names},
    }
    res = t.oms(spec, tmp_path)
    ref = t.reference("MarsEntryTruth", 2, 300, PARAMS, tmp_path)
    assert res["times"][-1] == 300.0 and len(res["result_times"]) == len(ref)
    t.assert_bitwise(res["series"]["truth"], names, ref, "FMI 3.0 truth in OMSimulator, 2 s")


def test_a_scenario_specific_fmi3_fmu_equals_its_fmi2_twin(tmp_path):
    """`fmu pack --fmi 3 --scenario msl-airdata`: arrays sized by the scenario's state dimension,
    every output bitwise equal to the FMI 2.0 pack of the same scenario."""
    for fmi in ("2", "3"):
        extra = ["--arrays"] if fmi == "3" else []
        r = run([ENTRYNAV, "fmu", "pack", "--fmi", fmi, *extra, "--scenario", "msl-airdata", "--out", tmp_path])
        assert r.returncode == 0, r.stderr
    f2, f3 = tmp_path / "MarsEntryNav_msl_airdata.fmu", tmp_path / "MarsEntryNav_msl_airdata-fmi3.fmu"
    assert validate_fmu(str(f3)) == []
    md = read_model_description(str(f2))
    outs = [v.name for v in md.modelVariables if v.causality == "output"]
    r2 = simulate_fmu(str(f2), output=outs)
    r3 = simulate_fmu(str(f3), output=[*outs, "est_x", "est_covariance"])
    assert [n for n in outs if not np.array_equal(_bits(r2[n]), _bits(r3[n]))] == []
    states = [v.name for v in md.modelVariables if v.name.startswith("est.")]
    assert r3["est_x"].shape == (len(r2), len(states))
    assert r3["est_covariance"].shape == (len(r2), len(states), len(states))
    for i, name in enumerate(states):
        assert np.array_equal(_bits(r3["est_x"][:, i]), _bits(r2[name]))
