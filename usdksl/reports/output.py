"""All-or-nothing output: every file is written to a temporary name beside its target and renamed into
place only after every file of the run has been written successfully.

A failure half way (a bad input found late, a full disk, an exception while formatting) therefore leaves
the output directories exactly as they were: no partial CSV, no stale override layer next to new CSVs.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Dict, List, Mapping, Optional, Union

from ..errors import UsdkslUsageError
from ..stopping import deferred_stops

TEMP_PREFIX = ".usdksl-tmp-"
_FILE_MODE = 0o666


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_writable_directory(directory: Union[str, Path]) -> Path:
    """Fail early (before the expensive check) when ``directory`` cannot receive files.

    A missing directory is fine when its nearest existing ancestor is a writable directory: it gets created
    at commit time. Raises UsdkslUsageError naming the directory otherwise.
    """
    directory = Path(directory)
    probe = directory
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise UsdkslUsageError("output directory cannot be written: not a directory", file=str(probe))
    with deferred_stops():   # a Ctrl-C must not leave the probe behind
        try:
            handle, name = tempfile.mkstemp(prefix=TEMP_PREFIX, dir=str(probe))
        except OSError as error:
            raise UsdkslUsageError(f"output directory cannot be written: {error.strerror}",
                                   file=str(probe)) from None
        os.close(handle)
        os.unlink(name)
    return directory


class OutputTransaction:
    """Collects named outputs in memory-backed temp files and publishes them together.

    Use as a context manager; files added with :meth:`write_text` / :meth:`write_bytes` appear at their
    target paths only when :meth:`commit` runs, and are all discarded when the block raises.
    """

    def __init__(self) -> None:
        self._pending: Dict[Path, bytes] = {}
        self._removals: List[Path] = []
        self._committed = False

    def write_text(self, target: Union[str, Path], text: str) -> None:
        self.write_bytes(target, text.encode("utf-8"))

    def write_bytes(self, target: Union[str, Path], data: bytes) -> None:
        if self._committed:
            raise RuntimeError("output transaction already committed")
        self._pending[Path(target)] = bytes(data)

    def remove(self, target: Union[str, Path]) -> None:
        """Remove ``target``, if it exists, once the new files are in place (an output that a run no longer
        writes, e.g. the override layer in its other format)."""
        if self._committed:
            raise RuntimeError("output transaction already committed")
        self._removals.append(Path(target))

    @property
    def targets(self) -> List[Path]:
        return list(self._pending)

    def commit(self) -> List[Path]:
        """Write every file to a temp name beside its target, then rename them all into place.

        Directories that did not exist are created and removed again when a write fails. Raises
        UsdkslUsageError (exit 2) naming the target that could not be written. A stop (Ctrl-C, SIGTERM,
        a timeout; usdksl.stopping) while the files are written removes them all again; creating a
        temporary file and the renames are never cut in half by one.
        """
        created_dirs: List[Path] = []
        temps: List[tuple] = []
        try:
            for target in self._pending:
                with deferred_stops():
                    created_dirs.extend(_make_directories(target.parent))
            for target, data in self._pending.items():
                with deferred_stops():
                    handle, temp_name = tempfile.mkstemp(prefix=TEMP_PREFIX, suffix=".part",
                                                         dir=str(target.parent))
                    temps.append((temp_name, target))
                with os.fdopen(handle, "wb") as stream:
                    stream.write(data)
                    stream.flush()
                    os.fsync(stream.fileno())
                os.chmod(temp_name, _FILE_MODE & ~_current_umask())  # mkstemp makes 0600; be a normal file
        except OSError as error:
            with deferred_stops():
                _discard(temps, created_dirs)
            failed = getattr(error, "filename", None) or (temps[-1][1] if temps else None)
            raise UsdkslUsageError(f"cannot write output: {error.strerror or error}", file=str(failed)) from None
        except BaseException:
            with deferred_stops():
                _discard(temps, created_dirs)
            raise
        with deferred_stops():
            for temp_name, target in temps:
                os.replace(temp_name, target)
            for stale in self._removals:
                try:
                    stale.unlink()
                except FileNotFoundError:
                    pass
                except OSError as error:
                    raise UsdkslUsageError(f"cannot remove stale output: {error.strerror or error}",
                                           file=str(stale)) from None
            self._committed = True
        return [target for _, target in temps]

    def __enter__(self) -> "OutputTransaction":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        # Nothing touched the disk before commit(): dropping the pending data is the whole rollback.
        if exc_type is not None:
            self._pending.clear()


def _make_directories(directory: Path) -> List[Path]:
    missing: List[Path] = []
    probe = directory
    while not probe.exists() and probe.parent != probe:
        missing.append(probe)
        probe = probe.parent
    for path in reversed(missing):
        path.mkdir()
    return missing


def _discard(temps, created_dirs) -> None:
    for temp_name, _ in temps:
        try:
            os.unlink(temp_name)
        except OSError:
            pass
    for directory in created_dirs:  # deepest first
        try:
            directory.rmdir()
        except OSError:
            pass


def resolve_output_path(value: Optional[str]) -> Optional[Path]:
    """``--json -`` means stdout and is not a file; anything else is a path."""
    if value is None or value == "-":
        return None
    return Path(value)


def write_files(files: Mapping[Union[str, Path], Optional[Union[str, bytes]]]) -> List[Path]:
    """Publish every ``{target: text or bytes}`` together (one :class:`OutputTransaction`), in the given
    order, and remove the targets whose value is None (stale outputs); returns the targets written.
    Raises UsdkslUsageError naming a target that could not be written."""
    transaction = OutputTransaction()
    for target, data in files.items():
        if data is None:
            transaction.remove(target)
        elif isinstance(data, bytes):
            transaction.write_bytes(target, data)
        else:
            transaction.write_text(target, data)
    return transaction.commit()


def write_text_atomic(target: Union[str, Path], text: str) -> Path:
    """Write one file the all-or-nothing way."""
    return write_files({target: text})[0]
