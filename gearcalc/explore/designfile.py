"""``--save DIR``: each optimum or front member as a ready design file, the original file with the varied keys set.

The original text is kept line for line (its comments too): a key's value is replaced on its own line (a
comment after the value stays), a key the file lacks is added at the end of its table (or in a new table at the
end).  A file that is not plain ``[table]`` / ``key = value`` lines where a varied key is (a dotted or inline-table
spelling), or standard input, is written anew from the data (without comments).  Files are created, never
replaced: an existing file of the same name is an error before anything is written.
"""
from __future__ import annotations

import os
import re

__all__ = ["with_values", "save_designs"]

_HEADER = re.compile(r"^\s*\[([A-Za-z0-9_\-]+)\]\s*(#.*)?$")
_KEY = r"^(\s*{name}\s*=\s*)(.*?)(\s*#.*)?$"


def _toml(value) -> str:
    import tomli_w

    return tomli_w.dumps({"v": value}).strip()[len("v = "):]


def with_values(text: str, values: dict) -> str | None:
    """``text`` (a TOML design) with the dotted keys of ``values`` set, comments kept; None when a key is not
    spelt as ``key = value`` under a plain ``[table]`` header.

    >>> print(with_values("[rows]\\ncount = 3  # rows\\n[sun]\\n", {"rows.count": 4, "sun.torque_Nm": 9.5}), end="")
    [rows]
    count = 4  # rows
    [sun]
    torque_Nm = 9.5
    """
    import tomllib

    lines = text.splitlines()
    for key, value in values.items():
        table, _, name = key.partition(".")
        start = end = None
        for k, line in enumerate(lines):
            m = _HEADER.match(line)
            if m:
                if start is not None and end is None:
                    end = k
                if m.group(1) == table:
                    start, end = k, None
        if start is None:
            lines += ["", f"[{table}]", f"{name} = {_toml(value)}"]
            continue
        end = len(lines) if end is None else end
        pattern = re.compile(_KEY.format(name=re.escape(name)))
        for k in range(start + 1, end):
            m = pattern.match(lines[k])
            if m:
                lines[k] = m.group(1) + _toml(value) + (m.group(3) or "")
                break
        else:
            last = end
            while last > start + 1 and not lines[last - 1].strip():
                last -= 1
            lines.insert(last, f"{name} = {_toml(value)}")
    out = "\n".join(lines) + "\n"
    try:
        data = tomllib.loads(out)
    except tomllib.TOMLDecodeError:
        return None
    for key, value in values.items():
        table, _, name = key.partition(".")
        if (data.get(table) or {}).get(name) != value:
            return None
    return out


def save_designs(folder: str, source: str, raw: dict, points: list[dict], stem: str | None = None) -> list[str]:
    """Write one design file per point (its varied keys' values) into ``folder`` (created when missing; its
    parent must exist): ``STEM.toml`` for one point, ``STEM_001.toml``... for several; the paths written.
    Raises ``FileExistsError`` naming the first file that exists (nothing is written then)."""
    import copy

    import tomli_w

    from ..design import apply_set

    text = None
    if source != "-" and os.path.isfile(source):
        with open(source, encoding="utf-8") as fh:
            text = fh.read()
    stem = stem or (os.path.splitext(os.path.basename(source))[0] if source != "-" else "design") + "_opt"
    names = [f"{stem}.toml"] if len(points) == 1 else [f"{stem}_{k + 1:03d}.toml" for k in range(len(points))]
    paths = [os.path.join(folder, n) for n in names]
    for p in paths:
        if os.path.lexists(p):
            raise FileExistsError(p)
    os.makedirs(folder, exist_ok=True)
    for p, point in zip(paths, points):
        out = with_values(text, point) if text is not None else None
        if out is None:
            data = copy.deepcopy(raw)
            apply_set(data, list(point.items()))
            out = tomli_w.dumps(data)
        with open(p, "x", encoding="utf-8") as fh:
            fh.write(out)
    return paths
