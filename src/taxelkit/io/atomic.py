"""Write output files atomically: a temporary file in the same folder, then a rename.

A reader never sees a half-written output, and a failed write leaves any
previous file exactly as it was.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
from collections.abc import Callable
from pathlib import Path

from taxelkit.errors import OutputExistsError, OutputWriteError, TaxelkitError

__all__ = ["atomic_write"]

#: Permission bits asked for when the temporary file is created; the process
#: umask is applied by the operating system, as for any newly created file.
_NEW_FILE_MODE = 0o666
#: How many random temporary names to try before giving up.
_MAX_TEMP_ATTEMPTS = 100


def _reason(exc: OSError) -> str:
    text = exc.strerror or str(exc) or type(exc).__name__
    return " ".join(text.split())


def _exists_message(target: Path) -> str:
    return f"{target}: already exists; use --force (force=True) to overwrite it"


def _temp_path_for(target: Path) -> Path:
    """Create an empty, exclusive temporary file beside ``target`` and return its path.

    The name is ``.{target.name}.tmp-{random}{target.suffix}``: hidden, in the same
    folder (so the final rename stays on one file system), and ending in the real
    suffix, which writers such as :func:`numpy.savez` and matplotlib use to pick or
    append a format.
    """
    for _ in range(_MAX_TEMP_ATTEMPTS):
        tmp = target.with_name(f".{target.name}.tmp-{secrets.token_hex(4)}{target.suffix}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, _NEW_FILE_MODE)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(errno.EEXIST, "no free temporary file name", str(target.parent))


def _publish(tmp: Path, target: Path, *, force: bool) -> None:
    """Move ``tmp`` to ``target``; without ``force`` never replace a file that exists."""
    if force:
        os.replace(tmp, target)
        return
    try:
        # A hard link fails if the target appeared since the first check: no clobbering.
        os.link(tmp, target)
    except FileExistsError:
        raise OutputExistsError(_exists_message(target)) from None
    except OSError:
        # The file system has no hard links (FAT, some network shares): check and rename.
        if os.path.lexists(target):
            raise OutputExistsError(_exists_message(target)) from None
        os.replace(tmp, target)
        return
    with contextlib.suppress(OSError):  # the output is in place; a stray link is harmless
        os.unlink(tmp)


def atomic_write(
    path: str | os.PathLike[str],
    writer: Callable[[Path], None],
    *,
    force: bool = False,
) -> Path:
    """Write a file through a temporary file and rename it into place.

    Parameters
    ----------
    path : str or os.PathLike
        Final output path. Its folder must exist.
    writer : callable
        ``writer(tmp)`` writes the complete output to the path ``tmp``. ``tmp``
        already exists as an empty file in the same folder as ``path`` and ends in
        the same suffix, so format-sniffing writers behave as for ``path``.
    force : bool, optional
        Replace ``path`` if it exists. Default ``False``.

    Returns
    -------
    pathlib.Path
        ``path``, now holding what ``writer`` wrote.

    Raises
    ------
    OutputExistsError
        If ``path`` exists (or appears while writing) and ``force`` is false.
    OutputWriteError
        If ``path`` is a folder, its folder does not exist, or the operating
        system refuses the write (an :class:`OSError` from ``writer`` included).
    Exception
        Whatever else ``writer`` raises, unchanged.

    Notes
    -----
    On any failure, the temporary file is removed and an existing ``path`` is left
    untouched. The rename is atomic on POSIX and on Windows (NTFS) within one
    folder. The data are not ``fsync``-ed, so the write is atomic but not durable
    against a power loss.

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> out = atomic_write(folder / "hello.txt", lambda tmp: tmp.write_text("hi"))
    >>> out.read_text()
    'hi'
    """
    target = Path(path)
    if target.is_dir():
        raise OutputWriteError(f"{target}: is a folder, not a file; give a file name")
    if not force and os.path.lexists(target):
        raise OutputExistsError(_exists_message(target))
    folder = target.parent
    if not folder.is_dir():
        raise OutputWriteError(f"{target}: folder {str(folder)!r} does not exist")
    try:
        tmp = _temp_path_for(target)
    except OSError as exc:
        raise OutputWriteError(
            f"{target}: cannot create a file in {str(folder)!r} ({_reason(exc)})"
        ) from exc
    try:
        writer(tmp)
        _publish(tmp, target, force=force)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError) and not isinstance(exc, TaxelkitError):
            raise OutputWriteError(f"{target}: cannot write ({_reason(exc)})") from exc
        raise
    return target
