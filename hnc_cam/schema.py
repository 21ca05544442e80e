"""Table-driven checks of the TOML files a user writes (tool library, machine file).

A table's schema maps each allowed key to a :class:`Key` (type, range, allowed values). The
check reports the first problem as one line with the file and the key's line::

    tools.toml:14: unknown key 'feed_finsh' (did you mean 'feed_finish'?)
    tools.toml:15: feed_rough = 25 is out of range (0.01-2 mm/rev)
    tools.toml:9: kind = "tunr" is not one of: turn, bore, thread, groove

:mod:`tomllib` gives no line numbers, so :func:`key_line` finds the key in the source text
(within the table's section; the ``index``-th one for an array of tables).

No heavy imports: the interpreter loads the machine file through this on its fast path.
"""
from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from .errors import HncError

__all__ = ["Key", "check_table", "key_line", "read_toml"]


@dataclass(frozen=True)
class Key:
    """One allowed key: ``kind`` is ``int``, ``float`` (an int is accepted), ``str``, ``bool``,
    ``strs`` (a string or a list of strings), ``table`` or ``any``.

    ``lo``/``hi``: inclusive range of a number (``lo_open``: lo itself is excluded);
    ``choices``: the allowed values of a string (each item of ``strs``); ``fold``: compare
    strings upper-cased; ``unit``: said in the range message.
    """
    kind: str = "float"
    lo: float | None = None
    hi: float | None = None
    unit: str = ""
    choices: tuple[str, ...] = ()
    required: bool = False
    lo_open: bool = False
    fold: bool = False


_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(?:#.*)?$")


def _norm_name(name: str) -> str:
    return ".".join(p.strip().strip('"').strip("'") for p in name.split("."))


def place(where: str, line: int | None) -> str:
    """``where:line`` of an error in a file, or ``where`` when the line is not known."""
    return f"{where}:{line}" if line else where


def key_line(text: str | None, table: str, key: str, index: int | None = None) -> int | None:
    """1-based line of ``key = ...`` inside the section ``[table]`` (or the ``index``-th
    ``[[table]]``; ``table = ""`` is the top level, where a key may also be a section's
    header ``[key]``), else the section's header line, else None."""
    if not text:
        return None
    key_re = re.compile(rf"^\s*(?:{re.escape(key)}|\"{re.escape(key)}\"|'{re.escape(key)}')\s*=")
    section = ""
    count = -1
    inside = table == "" and index is None
    header_line = None
    top_header = None
    for n, line in enumerate(text.splitlines(), 1):
        m = _HEADER.match(line)
        if m:
            section = _norm_name(m.group(2))
            if table == "" and top_header is None and section.split(".")[0] == key:
                top_header = n
            if section == table:
                if m.group(1) == "[[":
                    count += 1
                    inside = index is None or count == index
                else:
                    inside = index is None
                if inside:
                    header_line = n
            else:
                inside = False
            continue
        if inside and key_re.match(line):
            return n
    return header_line if header_line is not None else top_header


def _place(where: str, text: str | None, table: str, key: str, index: int | None) -> str:
    n = key_line(text, table, key, index)
    return f"{where}:{n}" if n is not None else where


def _g(v: float) -> str:
    return f"{v:g}"


def _range(k: Key) -> str:
    if k.lo is not None and k.hi is not None:
        s = f"{'above ' if k.lo_open else ''}{_g(k.lo)}-{_g(k.hi)}"
    elif k.lo is not None:
        s = f"{'more than' if k.lo_open else 'at least'} {_g(k.lo)}"
    else:
        s = f"at most {_g(k.hi)}" if k.hi is not None else "any"
    return f"{s} {k.unit}".strip()


def _show(v: Any) -> str:
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_show(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{...}"
    return repr(v) if not isinstance(v, (int, float)) else _g(v)


def _check_value(name: str, v: Any, k: Key) -> str | None:
    """None when ``v`` fits ``k``, else why (without the place)."""
    shown = f"{name} = {_show(v)}"
    if k.kind == "any":
        return None
    if k.kind == "bool":
        return None if isinstance(v, bool) else f"{shown} must be true or false"
    if k.kind == "table":
        return None if isinstance(v, Mapping) else f"{shown} must be a table"
    if k.kind in ("int", "float"):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or \
                (k.kind == "int" and not isinstance(v, int)):
            return f"{shown} must be {'an integer' if k.kind == 'int' else 'a number'}"
        if not math.isfinite(v):
            return f"{shown} must be a finite number"
        if (k.lo is not None and (v < k.lo or (k.lo_open and v == k.lo))) or \
                (k.hi is not None and v > k.hi):
            return f"{shown} is out of range ({_range(k)})"
        return None
    items: list[Any]
    if k.kind == "str":
        if not isinstance(v, str):
            return f"{shown} must be a string"
        items = [v]
    elif k.kind == "strs":
        items = [v] if isinstance(v, str) else list(v) if isinstance(v, list) else []
        if not isinstance(v, (str, list)) or not all(isinstance(x, str) for x in items):
            return f"{shown} must be a string or a list of strings"
    else:  # pragma: no cover - a schema bug
        raise ValueError(f"schema kind {k.kind!r}")
    if k.choices:
        allowed = {c.upper() if k.fold else c for c in k.choices}
        bad = [x for x in items if (x.upper() if k.fold else x) not in allowed]
        if bad:
            hint = difflib.get_close_matches(bad[0], k.choices, n=1, cutoff=0.6)
            mean = f" (did you mean {_show(hint[0])}?)" if hint else ""
            what = f"{_show(bad[0])} in {name}" if k.kind == "strs" else shown
            return f"{what} is not one of: {', '.join(k.choices)}{mean}"
    return None


def check_table(tbl: Any, schema: Mapping[str, Key], where: str, *, text: str | None = None,
                table: str = "", index: int | None = None,
                error: Callable[[str], Exception] = HncError, label: str | None = None) -> None:
    """Raise ``error("WHERE:LINE: ...")`` for the first unknown key, missing required key,
    wrong type, out-of-range number or value not among the choices of ``tbl``.

    ``where`` is the file; ``text`` its source (for line numbers); ``table``/``index`` say
    which section holds ``tbl``; ``label`` prefixes the key in messages (``tool T03``).
    """
    pre = f"{label}: " if label else ""
    if not isinstance(tbl, Mapping):
        n = key_line(text, table, "\0", index) if table else None
        raise error(f"{place(where, n)}: {pre}[{table}] must be a table")
    for name, v in tbl.items():
        k = schema.get(name)
        if k is None:
            hint = difflib.get_close_matches(str(name), list(schema), n=1, cutoff=0.6)
            mean = f" (did you mean '{hint[0]}'?)" if hint else \
                f" (allowed: {', '.join(schema)})"
            raise error(f"{_place(where, text, table, str(name), index)}: {pre}unknown key "
                        f"'{name}'{mean}")
        why = _check_value(str(name), v, k)
        if why:
            raise error(f"{_place(where, text, table, str(name), index)}: {pre}{why}")
    for name, k in schema.items():
        if k.required and name not in tbl:
            n = key_line(text, table, "\0", index)
            raise error(f"{place(where, n)}: {pre}{name} missing")


def read_toml(path: str, error: Callable[[str], Exception] = HncError,
              max_bytes: int = 16 * 1024 * 1024) -> tuple[dict, str]:
    """Read and parse a TOML file: ``(data, text)``. A file that cannot be read, is not a
    regular file, is too large, is not UTF-8 or is not valid TOML raises ``error`` with one
    line (``FILE:LINE:COL: ...`` for a syntax error)."""
    from .io import read_bytes

    raw = read_bytes(path, "a TOML file", error, max_bytes)
    return parse_toml(raw, path, error), raw.decode("utf-8", "replace")


def parse_toml(raw: bytes | str, where: str,
               error: Callable[[str], Exception] = HncError) -> dict:
    """Parse TOML bytes or text; bad encoding or syntax -> ``error`` with the place."""
    import tomllib

    from .io import decode_text

    text = decode_text(raw if isinstance(raw, bytes) else raw.encode("utf-8", "surrogatepass"),
                       where, "a TOML file", error)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        msg = str(e)
        m = re.search(r"\(at line (\d+), column (\d+)\)$", msg)
        if m:
            msg = msg[:m.start()].strip()
            raise error(f"{where}:{m.group(1)}:{m.group(2)}: not valid TOML: {msg}") from None
        raise error(f"{where}: not valid TOML: {msg}") from None
