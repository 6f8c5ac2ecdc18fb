from typing import Any, Literal, Optional

__version__: str

class Cond2:
    value: float
    lo: float
    hi: float
    proven: bool
    within_contract: bool
    route: str
    warnings: list[str]
    record: dict[str, Any]
    def __init__(self, record: dict[str, Any]) -> None: ...

def cond2(
    a: Any,
    tol: Optional[float] = None,
    storage: Literal["general", "lower", "upper"] = "general",
) -> Cond2: ...

def solve(
    K: Any,
    q: Any,
    D: Any,
    limits: Any,
    kinds: list[str],
    method: str = "condensed",
    *,
    eps: Optional[float] = None,
    factor: Optional[float] = None,
    delta: Optional[float] = None,
    tol: Optional[float] = None,
    adaptive: bool = False,
    metrics: bool = True,
    solver_metrics: Optional[bool] = None,
    cond_tol: Optional[float] = None,
    exact_start: bool = False,
    storage: Literal["general", "lower", "upper"] = "general",
    name: Optional[str] = None,
) -> dict[str, Any]: ...

def read_scene(path: Any) -> dict[str, Any]: ...
