"""Read a text file the user named (a case file, a torque history) with a size limit.

A file the user names may be anything: a device that never ends (``/dev/zero``), a
folder, a binary, a log of gigabytes given by mistake. It is read with
:data:`MAX_FILE_BYTES` at most, so that a wrong name costs a fraction of a second and one
line naming the key, not the machine's memory.
"""

from __future__ import annotations

from pathlib import Path

from spurdyn.errors import InputError

#: Bytes of a case file or a torque history: the longest history
#: (:data:`~spurdyn.history.MAX_HISTORY_POINTS`, a million, lines of three numbers at full precision,
#: about 80 bytes a line, 80 MB) fits, with room for comments.
MAX_FILE_BYTES = 128 << 20


def read_text(path: Path, key: str, missing: str = "no such file") -> str:
    """The text of ``path`` (UTF-8), read with :data:`MAX_FILE_BYTES` at most.

    Parameters
    ----------
    path : Path
        The file.
    key : str
        The key or option that named it, for the refusals (the file's own name when the
        key is the file, then not repeated in the reason).
    missing : str
        What to say when it does not exist.

    Raises
    ------
    InputError
        Naming ``key``, if the file is missing, unreadable, larger than the limit, or not
        UTF-8 text.
    """
    name = "" if key == str(path) else f"{str(path)!r} "
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise InputError(key, f"{name.rstrip() + ': ' if name else ''}{missing}") from None
    except IsADirectoryError:
        raise InputError(key, f"{name}is a folder, not a file") from None
    except (OSError, ValueError) as err:
        why = getattr(err, "strerror", None) or type(err).__name__
        raise InputError(key, f"{name}cannot be read ({why})") from None
    if len(data) > MAX_FILE_BYTES:
        raise InputError(key, f"{name}holds more than {MAX_FILE_BYTES >> 20} MiB (the most a "
                         "case file or a torque history may hold): is it the file you meant?")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(key, f"{name}is not UTF-8 text") from None


__all__ = ["MAX_FILE_BYTES", "read_text"]
