"""Type stubs of the native module (PyO3); use the typed API in `entrynav` instead."""

from typing import Callable, List, Optional, Tuple

def version() -> str: ...
def builtin_scenarios() -> List[Tuple[str, str]]: ...
def resolve_scenario(name_or_file: str) -> Tuple[str, str]: ...
def apply_sets(toml: str, sets: List[str]) -> str: ...
def scenario_json(toml: str) -> str: ...
def trade(
    toml: str,
    dir: str,
    filters: str,
    runs: Optional[int] = None,
    seed: int = 1,
    threads: Optional[int] = None,
    pcrlb: bool = True,
    progress: Optional[Callable[[int, int], object]] = None,
) -> Tuple[str, str, bool, bool]: ...
def trade_shard(
    toml: str,
    dir: str,
    filters: str,
    runs: int,
    seed: int,
    index: int,
    count: int,
    overrides: List[str],
    threads: Optional[int] = None,
) -> str: ...
def simulate(toml: str, dir: str, seed: int = 1, dispersed: bool = False) -> str: ...
def run_cli(args: List[str]) -> Tuple[int, str]: ...
