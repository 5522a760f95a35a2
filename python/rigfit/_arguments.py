"""The checks every public function makes on its arguments before any work.

A bad value raises :class:`rigfit.CampaignError` (a ValueError), a value of
the wrong type :class:`rigfit.ArgumentTypeError` (a TypeError); each message
names the keyword as the caller wrote it (``generations=-1``), never a CLI
flag. :func:`reworded` turns the CLI flags in the library's own messages
(``--overwrite``, ``--backend gpu``) into the package's keywords.
"""

import math
import numbers
import os
import re

import numpy as np

from .errors import ArgumentTypeError, CampaignError

#: The most threads a job may ask for.
MAX_THREADS = 1024

#: Counts (population, generations, modes, ...): at most what a usize holds
#: on every platform the package builds for; a seed: a u64.
MAX_COUNT = 2**63 - 1
MAX_SEED = 2**64 - 1


def _found(value):
    """What was given, as a message shows it: the type and a short repr."""
    text = repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    kind = type(value).__name__
    if isinstance(value, (bool, np.bool_)) or type(value) in (int, float, str):
        return text
    return f"{kind} {text}"


def _is_bool(value):
    return isinstance(value, (bool, np.bool_))


def integer(name, value, *, minimum=0, maximum=MAX_COUNT, optional=True):
    """An int (a Python or numpy integer, never a bool) in
    ``minimum..=maximum``; ``None`` passes when ``optional``."""
    if value is None and optional:
        return None
    if _is_bool(value) or not isinstance(value, (numbers.Integral, np.integer)):
        hint = ""
        if isinstance(value, (float, np.floating)) and math.isfinite(value) \
                and float(value).is_integer():
            hint = f" (write {int(value)})"
        raise ArgumentTypeError(
            f"{name}: expected an integer, found {_found(value)}{hint}")
    n = int(value)
    if n < minimum or n > maximum:
        if maximum >= MAX_COUNT:
            expected = f"an integer >= {minimum}"
        else:
            expected = f"an integer from {minimum} to {maximum}"
        raise CampaignError(f"{name}={n}: expected {expected}")
    return n


def real(name, value, *, optional=True, positive=False):
    """A finite float (a Python or numpy number, never a bool); ``None``
    passes when ``optional``."""
    if value is None and optional:
        return None
    if _is_bool(value) or not isinstance(value, (numbers.Real, np.integer, np.floating)):
        raise ArgumentTypeError(f"{name}: expected a number, found {_found(value)}")
    x = float(value)
    if not math.isfinite(x):
        raise CampaignError(f"{name}={x!r}: expected a finite number")
    if positive and x <= 0:
        raise CampaignError(f"{name}={x!r}: expected a number > 0")
    return x


def flag(name, value):
    """``True`` or ``False`` (numpy's bool too)."""
    if not _is_bool(value):
        raise ArgumentTypeError(f"{name}: expected True or False, found {_found(value)}")
    return bool(value)


def choice(name, value, choices, *, optional=True):
    """One of the strings ``choices``; ``None`` passes when ``optional``
    (the campaign's own setting)."""
    if value is None and optional:
        return None
    expected = ", ".join(f'"{c}"' for c in choices[:-1]) + f' or "{choices[-1]}"'
    if not isinstance(value, str):
        raise ArgumentTypeError(f"{name}: expected {expected}, found {_found(value)}")
    if value not in choices:
        raise CampaignError(f"{name}={value!r}: expected {expected}")
    return value


def text(name, value, *, optional=True):
    """A string; ``None`` passes when ``optional``."""
    if value is None and optional:
        return None
    if not isinstance(value, str):
        raise ArgumentTypeError(f"{name}: expected a string, found {_found(value)}")
    return value


def strings(name, value):
    """A sequence of strings (a tuple or list), as a list; a lone string is
    refused (it would be read as its letters)."""
    if isinstance(value, str):
        raise ArgumentTypeError(
            f"{name}: expected a sequence of strings, found the string {value!r} "
            f"(write ({value!r},) for one)")
    try:
        items = list(value)
    except TypeError:
        raise ArgumentTypeError(
            f"{name}: expected a sequence of strings, found {_found(value)}") from None
    for item in items:
        if not isinstance(item, str):
            raise ArgumentTypeError(
                f"{name}: expected a sequence of strings, found {_found(item)} in it")
    return items


def path(name, value, *, optional=True):
    """A folder or file path (a str or os.PathLike), as a str."""
    if value is None and optional:
        return None
    if isinstance(value, bytes) or not isinstance(value, (str, os.PathLike)):
        raise ArgumentTypeError(
            f"{name}: expected a path (a str or pathlib.Path), found {_found(value)}")
    p = os.fspath(value)
    if not isinstance(p, str):
        raise ArgumentTypeError(
            f"{name}: expected a path (a str or pathlib.Path), found {_found(value)}")
    if not p or "\0" in p:
        raise CampaignError(f"{name}={p!r}: expected a path to a folder")
    return p


def campaign(value, name="campaign"):
    """A :class:`rigfit.Campaign`; says how to make one from what was given."""
    from .campaign import Campaign
    if isinstance(value, Campaign):
        return value
    if isinstance(value, (str, os.PathLike)):
        hint = f"; load the file with rigfit.Campaign.from_json({os.fspath(value)!r})"
    elif isinstance(value, dict):
        hint = "; build one from the dict with rigfit.Campaign.from_dict(d)"
    else:
        hint = ("; load a campaign file with rigfit.Campaign.from_json(path) or build one "
                "from a dict with rigfit.Campaign.from_dict(d)")
    raise ArgumentTypeError(f"{name}: expected a rigfit.Campaign, found {_found(value)}{hint}")


def threads(value, name="threads"):
    """The CPU threads: 0 (all the cores) up to :data:`MAX_THREADS`."""
    return integer(name, value, minimum=0, maximum=MAX_THREADS, optional=False)


def adapter(value, name="adapter"):
    """The GPU adapter: its index as ``rigfit devices`` lists it (an int or
    a str), a PCI bus id or a piece of its name."""
    if value is None:
        return None
    if not _is_bool(value) and isinstance(value, (numbers.Integral, np.integer)):
        if int(value) < 0:
            raise CampaignError(f"{name}={int(value)}: expected an adapter's index >= 0")
        return str(int(value))
    if not isinstance(value, str):
        raise ArgumentTypeError(
            f"{name}: expected an index, a PCI bus id or a piece of an adapter's name, "
            f"found {_found(value)}")
    return value


_SIZE = re.compile(r"^(\d+\.?\d*|\.\d+)([eE]\d+)?$")
_UNITS = {"": 1.0, "k": 1024.0, "m": 1024.0**2, "g": 1024.0**3, "t": 1024.0**4}


def _size_bytes(s):
    """A size as ``rigfit run --max-memory`` reads it (the library's
    ``parse_bytes``): a number and K, M, G or T (powers of 1024, an optional
    ``i`` and ``B``), or ``None``."""
    t = s.strip()
    split = len(t)
    for i, ch in enumerate(t):
        if not (ch.isascii() and (ch.isdigit() or ch in ".eE")):
            split = i
            break
    num, unit = t[:split], t[split:].strip().lower()
    if not _SIZE.match(num):
        return None
    unit = unit.rstrip("b").rstrip("i")
    if unit not in _UNITS:
        return None
    b = float(num) * _UNITS[unit]
    return b if math.isfinite(b) and b > 0 else None


def max_memory(value, name="max_memory"):
    """Bytes (a number > 0) or a size string (``"512M"``, ``"2G"``)."""
    if value is None:
        return None
    expected = "a size > 0 in bytes or with K, M, G or T (512M, 2G)"
    if isinstance(value, str):
        if _size_bytes(value) is None:
            raise CampaignError(f"{name}: expected {expected}, found {value!r}")
        return value
    if _is_bool(value) or not isinstance(value, (numbers.Real, np.integer, np.floating)):
        raise ArgumentTypeError(f"{name}: expected {expected}, found {_found(value)}")
    x = float(value)
    if not (math.isfinite(x) and x > 0):
        raise CampaignError(f"{name}: expected {expected}, found {_found(value)}")
    return x


def progress(value, name="progress"):
    """``True``/``False`` or a callable."""
    if callable(value) or _is_bool(value) or value is None:
        return value
    raise ArgumentTypeError(
        f"{name}: expected True, False or a callable taking a dict, found {_found(value)}")


# The CLI's flags in the library's messages, in the package's keywords.
_FLAGS = [
    (re.compile(r"--(overwrite|resume)\b"), lambda m: f"{m.group(1)}=True"),
    (re.compile(r"--(backend|precision|method) (auto|gpu|cpu|f32|f64|ga|cmaes)\b"),
     lambda m: f'{m.group(1)}="{m.group(2)}"'),
    (re.compile(r"--adapter (\S+)"), lambda m: f"adapter={m.group(1)}"),
    (re.compile(r"--(adapter|population|generations|seed|threads|target-fitness|max-memory"
                r"|backend|precision|method|out)(?: (\d\S*))?(?![\w-])"),
     lambda m: m.group(1).replace("-", "_") + (f"={m.group(2)}" if m.group(2) else "")),
]


def reworded(message):
    """``message`` with the CLI's flags written as the package's keywords
    (``--overwrite`` as ``overwrite=True``, ``--backend gpu`` as
    ``backend="gpu"``)."""
    for pattern, repl in _FLAGS:
        message = pattern.sub(repl, message)
    return message


def reword(error):
    """Rewrites ``error``'s message in place (same type, same traceback)."""
    if error.args and isinstance(error.args[0], str):
        error.args = (reworded(error.args[0]),) + error.args[1:]
    return error
