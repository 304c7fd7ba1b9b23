"""Names of a package imported on first use (PEP 562), so that importing one of its small modules does not import
the whole package's machinery (usdksl.pipeline, usdksl.scale)."""

from importlib import import_module
from typing import Callable, Dict, List, MutableMapping, Tuple


def lazy_exports(package: str, exports: Dict[str, str],
                 namespace: MutableMapping[str, object]) -> Tuple[Callable[[str], object], Callable[[], List[str]]]:
    """``(__getattr__, __dir__)`` for ``package``, whose public ``exports`` map a name to the module defining it;
    a name looked up once is kept in ``namespace`` (the package's globals)."""
    def getattr_(name: str) -> object:
        module_name = exports.get(name)
        if module_name is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(module_name), name)
        namespace[name] = value
        return value

    def dir_() -> List[str]:
        return sorted(set(namespace) | set(exports))

    return getattr_, dir_
