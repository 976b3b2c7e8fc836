"""entrynav from Python: Mars entry navigation scenarios and Monte Carlo trades of navigation filters.

>>> import entrynav
>>> sc = entrynav.Scenario.builtin("four-beacon-fusion")
>>> res = entrynav.trade(sc, ["ekf", "dcifaif"], runs=200, seed=1)
>>> res.rmse("ekf")["pos_m"]          # position RMSE per epoch, a pandas Series
>>> moved = sc.set("beacons.0.lat_deg", 3.0)   # a new Scenario; `sc` is unchanged

The same engine as the `entrynav` command: `trade(...)` with the same scenario, filters, runs and
seed gives the CLI's `--json` summary bit for bit (outside `provenance` and `timing`), on any
number of threads. Runs execute in Rust with the GIL released; Ctrl-C raises KeyboardInterrupt
within a fraction of a second, and the runs finished so far are on the exception's `partial`
attribute (a `TradeResult` with `complete == False`), as the CLI keeps them on SIGINT.

Errors: `ValueError` for a bad field or argument (the message names the field, the value and the
allowed range, as the CLI's), `FileNotFoundError` for a scenario file that does not exist,
`RuntimeError` for a numerical failure.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

from . import _entrynav

__all__ = [
    "Scenario",
    "TradeResult",
    "DesignResult",
    "builtin_scenarios",
    "simulate",
    "trade",
    "trade_shard",
    "tune",
    "observe",
    "optimize_ground",
    "optimize_select",
    "optimize_orbiters",
    "deliver",
    "fmu_pack",
    "__version__",
]

__version__ = _entrynav.version()


def _toml_value(value: Any) -> str:
    """A Python value in TOML syntax (what `--set PATH=VALUE` expects)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_toml_value(v)}" for k, v in value.items()) + "}"
    try:  # numpy scalars
        return _toml_value(value.item())
    except AttributeError:
        raise TypeError(f"cannot write a {type(value).__name__} as a scenario value") from None


def _shown(value: Any) -> str:
    """A value as a message quotes it: its repr, at most 60 characters."""
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:50]}… ({len(text)} characters)"


def _text(key: str, value: Any, what: str = "a string") -> str:
    """`value` of keyword `key` as a string (a path-like object too), else TypeError naming it."""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if not isinstance(value, str):
        raise TypeError(f"{key} = {_shown(value)} has the wrong type: must be {what}, not {type(value).__name__}")
    return value


def _whole(key: str, value: Any, lo: int, hi: int) -> int:
    """A whole number of keyword `key` in `lo..=hi`: TypeError for another type, ValueError out of range."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{key} = {_shown(value)} has the wrong type: must be a whole number (an int)")
    if not lo <= value <= hi:
        raise ValueError(f"{key} = {value} is out of range: must be from {lo} to {hi}")
    return value


def _filter_names(value: Any, key: str = "filters") -> List[str]:
    """A filter name or a list of them (the study layer checks the names)."""
    if isinstance(value, str):
        return [value]
    if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
        if not value:
            raise ValueError(f"{key} = []: name at least one filter (ekf, ukf, ci, dcifaif, ...)")
        return list(value)
    raise TypeError(f"{key} = {_shown(value)} has the wrong type: must be a filter name or a list of them "
                    "(ekf, ukf, ci, dcifaif, ...)")


class Scenario:
    """A validated scenario: its TOML text and the folder its relative file names resolve against.

    Scenarios are values: `set` returns a new, re-validated Scenario.
    """

    def __init__(self, toml: str, folder: Union[str, Path] = "."):
        # Validate now, so a Scenario always holds a valid configuration.
        self._toml = _entrynav.apply_sets(toml, [])
        self._folder = str(folder)

    @classmethod
    def builtin(cls, name: str) -> "Scenario":
        """A built-in scenario by name (see `builtin_scenarios()`)."""
        name = _text("name", name)
        if name not in builtin_scenarios():
            import difflib

            near = difflib.get_close_matches(name.lower(), list(builtin_scenarios()), n=1, cutoff=0.8)
            hint = f"; did you mean {near[0]!r}?" if near else ""
            raise ValueError(f"name = {_shown(name)} is not a built-in scenario: must be one of "
                             f"{', '.join(builtin_scenarios())}{hint}")
        toml, folder = _entrynav.resolve_scenario(name)
        return cls(toml, folder)

    @classmethod
    def from_file(cls, path: Union[str, Path]) -> "Scenario":
        """A scenario TOML file; files it names are read relative to its folder."""
        text = _text("path", path, "a file path")
        try:
            toml, folder = _entrynav.resolve_scenario(text)
        except (FileNotFoundError, ValueError) as e:
            raise type(e)(f"path = {_shown(text)}: {e}") from None
        return cls(toml, folder)

    def set(self, path: str, value: Any) -> "Scenario":
        """A copy with field `path` (dotted, numeric keys index arrays: `beacons.0.lat_deg`) set
        to `value`, validated as `--set path=value` is; `ValueError` names a bad field or value."""
        field = _text("path", path, "a dotted field name")
        try:
            toml = _entrynav.apply_sets(self._toml, [f"{field}={_toml_value(value)}"])
        except ValueError as e:
            # An override that cannot be applied (no such field, a value of the wrong type) is
            # said in the call's terms; a value out of its range keeps the field's own message
            # (`beacons[0].lat_deg = 123.0 is invalid: allowed [-90, 90] deg`).
            text = str(e)
            if text.startswith("--set '") and "': " in text:
                reason = text.split("': ", 1)[1]
                raise ValueError(f"set(path={_shown(field)}, value={_shown(value)}): {reason}") from None
            raise
        return Scenario(toml, self._folder)

    def with_sets(self, sets: Iterable[str]) -> "Scenario":
        """A copy with the CLI's `--set PATH=VALUE` strings applied (VALUE in TOML syntax)."""
        toml = _entrynav.apply_sets(self._toml, list(sets))
        return Scenario(toml, self._folder)

    def to_toml(self) -> str:
        """The scenario as TOML (what `entrynav trade --scenario FILE` reads back)."""
        return self._toml

    def to_dict(self) -> Dict[str, Any]:
        """Every field of the scenario, defaults filled in."""
        return json.loads(_entrynav.scenario_json(self._toml))

    @property
    def name(self) -> str:
        return self.to_dict()["name"]

    @property
    def folder(self) -> str:
        return self._folder

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Scenario) and (self._toml, self._folder) == (other._toml, other._folder)

    def __repr__(self) -> str:
        return f"Scenario({self.name!r})"


def builtin_scenarios() -> Dict[str, str]:
    """Built-in scenario names with a one-line description (paper, states, sensors, beacons)."""
    return dict(_entrynav.builtin_scenarios())


class TradeResult:
    """The outcome of `trade`: the summary (the CLI's JSON) and the per-epoch series."""

    def __init__(self, summary: Dict[str, Any], details: Dict[str, Any], scenario: Scenario, filters: List[str],
                 native: Any = None):
        self.summary = summary
        self._details = details
        self._native = native
        self.scenario = scenario
        self.filters = filters

    @property
    def complete(self) -> bool:
        """False when the trade was interrupted: the statistics are those of the finished runs."""
        return bool(self.summary["complete"])

    def _filter(self, name: str) -> Dict[str, Any]:
        if name not in self._details["filters"]:
            raise ValueError(f"filter '{name}' is not in this trade ({', '.join(self.filters)})")
        return self._details["filters"][name]

    def series(self, filter: str, key: str):
        """One statistic of `filter` per epoch as a read-only numpy float64 array that views the
        native result's bytes (no copy): `times_s`, `pos_rmse_m`, `vel_rmse_mps`, `nees_mean`,
        `nees_kinematic_mean`, `nis_mean`, the `density_*` series (shape `(epochs,)`), and
        `rmse`, `sigma_mean`, `bias` (shape `(epochs, states)`, columns in `summary["states"]`
        order) and `local_rmse_m` (shape `(3, epochs)`: downrange, crossrange, up). NaN where a
        value is undefined."""
        import numpy as np

        self._filter(filter)
        if self._native is None:
            s = self._filter(filter)["series"]
            if key not in s:
                raise ValueError(f"series '{key}' does not exist")
            return np.array(s[key], dtype=float)
        raw, rows, cols = self._native.series(filter, key)
        a = np.frombuffer(raw, dtype="<f8")
        return a.reshape(rows, cols) if key in ("rmse", "sigma_mean", "bias", "local_rmse_m") else a

    def rmse(self, filter: str):
        """RMSE over runs per epoch (pandas DataFrame indexed by time in s): one column per
        state, then `pos_m`, `vel_mps`, `downrange_m`, `crossrange_m`, `up_m`."""
        import pandas as pd

        times = self.series(filter, "times_s")
        rmse = self.series(filter, "rmse")
        states = self.summary["states"]
        data = {st: rmse[:, i] for i, st in enumerate(states)}
        data["pos_m"] = self.series(filter, "pos_rmse_m")
        data["vel_mps"] = self.series(filter, "vel_rmse_mps")
        local = self.series(filter, "local_rmse_m")  # [component][epoch]
        for j, name in enumerate(["downrange_m", "crossrange_m", "up_m"]):
            data[name] = local[j] if j < len(local) else [None] * len(times)
        return pd.DataFrame(data, index=pd.Index(times, name="t_s"), dtype=float)

    def sigma(self, filter: str):
        """Mean onboard 1σ over runs per epoch and state (DataFrame indexed by time in s)."""
        import pandas as pd

        sigma = self.series(filter, "sigma_mean")
        data = {st: sigma[:, i] for i, st in enumerate(self.summary["states"])}
        return pd.DataFrame(data, index=pd.Index(self.series(filter, "times_s"), name="t_s"), dtype=float)

    def nees(self, filter: str):
        """Mean NEES and NIS over runs per epoch with the two-sided 95 % χ² bands of the means
        (DataFrame indexed by time in s)."""
        import pandas as pd

        times = self.series(filter, "times_s")
        f = next(f for f in self.summary["filters"] if f["name"] == filter)
        lo, hi = f["nees_bounds_95"]
        nlo, nhi = f["nis_bounds_95"] if f.get("nis_bounds_95") else (None, None)
        n = len(times)
        return pd.DataFrame(
            {
                "nees": self.series(filter, "nees_mean"),
                "nees_lower": [lo] * n,
                "nees_upper": [hi] * n,
                "nis": self.series(filter, "nis_mean"),
                "nis_lower": [nlo] * n,
                "nis_upper": [nhi] * n,
            },
            index=pd.Index(times, name="t_s"),
            dtype=float,
        )

    def final_errors(self):
        """One row per run and filter: run, filter, status, the final error per state, `pos_m`,
        `vel_mps`, `nees` (the CLI's `_final_errors.csv`)."""
        import pandas as pd

        rows = []
        states = self.summary["states"]
        for name in self.filters:
            for r in self._filter(name)["final_errors"]:
                row = {"run": r["run"], "filter": name, "status": r["status"]}
                row.update({f"err_{st}": (r["err"][i] if i < len(r["err"]) else None) for i, st in enumerate(states)})
                row.update({"pos_m": r["pos_m"], "vel_mps": r["vel_mps"], "nees": r["nees"]})
                rows.append(row)
        return pd.DataFrame(rows)

    def pcrlb(self):
        """The PCRLB per epoch (DataFrame indexed by time in s), or None without one."""
        import pandas as pd

        b = self.summary.get("pcrlb")
        if not b or not b.get("available"):
            return None
        return pd.DataFrame(b["series"], index=pd.Index(b["times_s"], name="t_s"), dtype=float)

    def report(self, path: Union[str, Path]) -> Path:
        """Write the self-contained HTML report (`entrynav trade --report PATH`): recommendation,
        verdicts, RMSE against the PCRLB, errors and ±3σ, NEES/NIS, dispersion. Returns the path."""
        self._native.write_report(_text("path", path, "a file path"))
        return Path(path)

    def to_json(self, path: Union[str, Path]) -> None:
        """Write the summary as the CLI writes `--json` (with its `provenance`, which names the
        Python call, and `timing`), whole or not at all."""
        self._native.write_json(_text("path", path, "a file path"))

    def __repr__(self) -> str:
        state = "complete" if self.complete else f"interrupted after {self.summary['runs_completed']} runs"
        return f"TradeResult({self.summary['scenario']!r}, {', '.join(self.filters)}, {self.summary['runs']} runs, {state})"


def _progress_callback(progress: Any) -> Optional[Callable[[int, int], Any]]:
    if progress is None or progress is False:
        return None
    if callable(progress):
        return progress
    if progress is True or progress == "tqdm":
        try:
            from tqdm.auto import tqdm
        except ImportError:
            raise ValueError("progress=True needs tqdm (pip install tqdm), or pass a callable(done, total)") from None
        bar: List[Any] = []

        def update(done: int, total: int) -> None:
            if not bar:
                bar.append(tqdm(total=total, unit="run"))
            bar[0].n = done
            bar[0].refresh()
            if done >= total:
                bar[0].close()

        return update
    raise ValueError(f"progress = {progress!r}: expected None, True, 'tqdm' or a callable(done, total)")


def trade(
    scenario: Union[Scenario, str],
    filters: Union[Sequence[str], str] = ("ekf",),
    runs: Optional[int] = None,
    seed: int = 1,
    threads: Optional[int] = None,
    pcrlb: bool = True,
    progress: Any = None,
    method: str = "mc",
) -> TradeResult:
    """A Monte Carlo trade of `filters` on `scenario` (a Scenario or a built-in name): `runs`
    (default the scenario's `monte_carlo.runs`), master `seed`, on `threads` workers (default all
    cores; the result does not depend on it), with the PCRLB unless `pcrlb=False`; `method="both"`
    adds LinCov of each filter beside the Monte Carlo (the summary's `lincov` block). Every value is
    checked by the study layer before any run, with the command line's message.

    `progress`: a callable `(done, total)`, or True / "tqdm" for a tqdm bar.
    """
    scenario = _scenario(scenario)
    names = _filter_names(filters)
    summary, details, interrupted, native = _entrynav.trade(
        scenario.to_toml(),
        scenario.folder,
        _options(filters=",".join(names), runs=runs, seed=seed, threads=threads, pcrlb=pcrlb, method=method),
        _progress_callback(progress),
    )
    result = TradeResult(json.loads(summary), json.loads(details), scenario, names, native)
    if interrupted:
        err = KeyboardInterrupt(
            f"trade interrupted: {result.summary['runs_completed']} of {result.summary['runs']} runs finished; "
            "they are on this exception's `partial` attribute"
        )
        err.partial = result  # type: ignore[attr-defined]
        raise err
    return result


def trade_shard(
    scenario: Union[Scenario, str],
    filters: Union[Sequence[str], str],
    runs: int,
    seed: int,
    index: int,
    count: int,
    overrides: Sequence[str] = (),
    threads: Optional[int] = None,
) -> str:
    """Shard `index` of `count` of a study, as the JSON text `entrynav trade --shard I/N --json
    FILE` writes: `entrynav trade merge` combines shards from either into exactly the
    single-process result. `overrides` are the `--set` strings already applied to `scenario`
    (recorded in the shard's provenance, which merge checks across shards)."""
    scenario = _scenario(scenario)
    names = _filter_names(filters)
    if not isinstance(overrides, (list, tuple)) or not all(isinstance(o, str) for o in overrides):
        raise TypeError(f"overrides = {_shown(overrides)} has the wrong type: must be a list of PATH=VALUE strings")
    count = _whole("count", count, 1, 1_000_000)
    index = _whole("index", index, 0, count - 1)
    return _entrynav.trade_shard(
        scenario.to_toml(), scenario.folder, index, count, list(overrides),
        _options(filters=",".join(names), runs=runs, seed=seed, threads=threads),
    )


def simulate(scenario: Union[Scenario, str], seed: int = 1, dispersed: bool = False):
    """One truth run with its measurement record (`entrynav simulate --out FILE`): a pandas
    DataFrame with the CLI's columns (time, spherical state, altitude, density, dynamic pressure,
    heating, aerodynamic acceleration, Cartesian state for a Cartesian truth, beacon visibility,
    one column per measurement channel, NaN where not sampled). `df.attrs` holds `stop` (duration,
    stop_speed, ground) and `peaks` (value and time of the peak deceleration, dynamic pressure and
    heating over every integration step)."""
    import pandas as pd

    scenario = _scenario(scenario)
    doc = json.loads(_entrynav.simulate(scenario.to_toml(), scenario.folder, _options(seed=seed, dispersed=dispersed)))
    df = pd.DataFrame(doc["rows"], columns=doc["columns"], dtype=float)
    df.attrs["stop"] = doc["stop"]
    df.attrs["peaks"] = doc["peaks"]
    return df


def _options(**options: Any) -> Dict[str, Any]:
    """Keyword arguments for a study, without those left at None (the study's default)."""
    return {k: v for k, v in options.items() if v is not None}


def _scenario(scenario: Union[Scenario, str]) -> Scenario:
    """A Scenario, a built-in's name or a scenario file's path, as a Scenario."""
    if isinstance(scenario, Scenario):
        return scenario
    name = _text("scenario", scenario, "a Scenario, a built-in name or a scenario file path")
    if name in builtin_scenarios():
        return Scenario.builtin(name)
    # The loader's message names the scenario (and the nearest built-in for a near miss).
    toml, folder = _entrynav.resolve_scenario(name)
    return Scenario(toml, folder)


# ---------------------------------------------------------------------------------------------
# The design studies: the study layer's functions the `entrynav` command calls, with their
# options as keyword arguments (the command line's flags with `_` for `-`), checked by the study
# layer with the command line's messages: ValueError for a value out of range, TypeError for an
# unknown keyword or a value of the wrong type.


def tune(
    scenario: Union[Scenario, str],
    filters: Union[Sequence[str], str] = ("ekf",),
    runs: int = 24,
    seed: int = 1,
    validation_runs: int = 100,
    tune_noise: bool = False,
    nis_only: bool = False,
    max_evaluations: int = 150,
    threads: Optional[int] = None,
    force: bool = False,
) -> Scenario:
    """`entrynav tune`: each filter's process noise (and with `tune_noise` its assumed measurement
    noise) tuned to consistency, validated on fresh runs; returns the tuned Scenario (one
    `[filter.tuned.<name>]` table per filter). A tuning that makes a filter worse on the fresh
    runs (a primary figure worse beyond the Monte Carlo noise) is refused with RuntimeError naming
    the filter and figure, unless `force`. A tuning that is still inconsistent raises RuntimeError
    naming the channel, states, epochs and likely cause, with the tuned Scenario on its `result`
    (the CLI writes the file and exits 1)."""
    sc = _scenario(scenario)
    names = _filter_names(filters)
    text, inconsistent = _entrynav.tune(sc.to_toml(), sc.folder, _options(
        filters=",".join(names), runs=runs, seed=seed, validation_runs=validation_runs, tune_noise=tune_noise,
        nis_only=nis_only, max_evaluations=max_evaluations, threads=threads, force=force))
    result = Scenario(text, sc.folder)
    if inconsistent is not None:
        err = RuntimeError(inconsistent)
        err.result = result  # type: ignore[attr-defined]
        raise err
    return result


def observe(scenario: Union[Scenario, str], method: str = "lie", step: float = 1.0, fim: bool = False,
            **options: Any) -> Dict[str, Any]:
    """`entrynav observe --json`: the degree of observability δ(t) along the trajectory (and with
    `fim` the beacons' Fisher information) as the JSON dict the CLI writes. Further options as
    keywords: `subsystems`, `beacons`, `pcrlb`, `runs`, `seed`."""
    sc = _scenario(scenario)
    return json.loads(_entrynav.observe(sc.to_toml(), sc.folder, _options(method=method, step=step, fim=fim, **options)))


def deliver(
    scenario: Union[Scenario, str],
    filters: Union[Sequence[str], str] = ("ekf",),
    runs: int = 100,
    seed: int = 1,
    threads: Optional[int] = None,
) -> Dict[str, Any]:
    """`entrynav guidance deliver`: a scenario with `[guidance]` (e.g. the built-ins `msl-guided`,
    `four-beacon-fusion-guided`) flown `runs` times with each filter's estimate in the guidance
    loop, with perfect navigation and the unguided reference bank on the same draws. Returns the
    CLI's JSON: `{"delivery": {..., "rows": [{name, deployed, failures, rms_miss_m, ellipse_99,
    rms_nav_position_error_m, ...}]}, "runs": [...]}` (docs/guidance.md). A scenario without
    `[guidance]` raises ValueError."""
    sc = _scenario(scenario)
    names = _filter_names(filters)
    text = _entrynav.deliver(sc.to_toml(), sc.folder, _options(filters=",".join(names), runs=runs, seed=seed,
                                                               threads=threads))
    return json.loads(text)


class DesignResult:
    """An optimizer's answer: `summary` (its `--json`, with the `check` of the optimum against the
    input design by the bound and a Monte Carlo) and `scenario` (the written scenario)."""

    def __init__(self, summary: Dict[str, Any], scenario: Scenario):
        self.summary = summary
        self.scenario = scenario

    def __repr__(self) -> str:
        return f"DesignResult({self.scenario.name!r})"


def _design(native: Callable[..., Any], scenario: Union[Scenario, str], options: Dict[str, Any]) -> DesignResult:
    sc = _scenario(scenario)
    summary, toml, refusal = native(sc.to_toml(), sc.folder, _options(**options))
    result = DesignResult(json.loads(summary), Scenario(toml, sc.folder))
    if refusal is not None:
        err = RuntimeError(refusal)
        err.result = result  # type: ignore[attr-defined]
        raise err
    return result


def optimize_ground(scenario: Union[Scenario, str], beacons: Optional[int] = None, **options: Any) -> DesignResult:
    """`entrynav optimize ground`: surface beacon sites (defaults: the navigation objective, the
    separation constraint, the check against the input design). Options as keywords, named as
    the CLI's flags (`objective="min-delta"`, `min_separation_deg=2.0`, `starts=4`, `check_runs=100`,
    `no_check=True`, ...). A design worse than the input raises RuntimeError (the CLI's exit 1)
    whose `result` attribute holds the design."""
    return _design(_entrynav.optimize_ground, scenario, dict(beacons=beacons, **options))


def optimize_select(scenario: Union[Scenario, str], k: int, grid_deg: float = 0.5, exact: bool = False,
                    **options: Any) -> DesignResult:
    """`entrynav optimize select`: k sites of a candidate grid, certified with `exact`; further
    options as keywords (`min_separation_deg`, `criterion`, `region=[lat_min, lat_max, lon_min,
    lon_max]`, `time_limit`, ...)."""
    return _design(_entrynav.optimize_select, scenario, dict(k=k, grid_deg=grid_deg, exact=exact, **options))


def optimize_orbiters(scenario: Union[Scenario, str], **options: Any) -> DesignResult:
    """`entrynav optimize orbiters`: orbital elements (Ω, i, f) of the relay orbiters; options as
    keywords (`orbiters`, `altitude_km`, `objective`, ...)."""
    return _design(_entrynav.optimize_orbiters, scenario, options)


def fmu_pack(out: Union[str, Path], scenario: Optional[Union[Scenario, str]] = None, filter: Optional[str] = None,
             fmi: int = 2, library: Optional[Union[str, Path]] = None, ssp: bool = False,
             keep_symbols: bool = False, arrays: bool = False) -> List[Path]:
    """`entrynav fmu pack`: the FMUs into `out` (FMI 2.0, or 3.0 with `fmi=3`; with `ssp` also the
    SSP packages); with `scenario` the combined FMU specific to it, `filter` its default filter.
    `arrays` (FMI 3.0 only) also declares the arrays est_x, est_sigma, est_covariance, which
    OMSimulator 3.0 cannot load.
    `library` is the FMU shared library (target/release/libentrynav_fmu.so; default
    $ENTRYNAV_FMU_LIB). Returns the paths written, sorted."""
    out = _text("out", out, "a folder path")
    lib = library if library is not None else os.environ.get("ENTRYNAV_FMU_LIB")
    if lib is None:
        raise ValueError("library = None: fmu_pack needs library= (target/release/libentrynav_fmu.so) or "
                         "$ENTRYNAV_FMU_LIB")
    lib = _text("library", lib, "a file path")
    builtin = toml = folder = None
    if scenario is not None:
        sc = _scenario(scenario)
        # An unchanged built-in is packed from its own text (comments kept), as the CLI does.
        if sc.name in builtin_scenarios() and Scenario.builtin(sc.name) == sc:
            builtin = sc.name
        else:
            toml, folder = sc.to_toml(), sc.folder
    options = _options(filter=filter, fmi=fmi, ssp=ssp, keep_symbols=keep_symbols, arrays=arrays)
    return sorted(Path(p) for p in _entrynav.fmu_pack(str(out), str(lib), builtin, toml, folder, options))
