#!/usr/bin/env python3
"""Import circles between the files of each crate, and the largest crates and files.

    python3 scripts/import_cycles.py [--why] [CRATE_DIR ...]   (default: every crates/*)

A file imports another when it names an item of the other's module: `use crate::a::b`,
`super::x`, `self::child::y`, or a path through one of its own child modules (`child::Z`),
in a `use` declaration or inline, followed through re-exports to the file that defines it. A
path in an attribute string counts as the compiler reads it: `#[serde(with = "crate::a::b")]`
(and `default`, `serialize_with`, `deserialize_with`, `skip_serializing_if`, `from`,
`try_from`, `into`, `remote`, `getter`) names the module or function it holds, and
`#[path = "f.rs"] mod x;` makes `f.rs` (beside the declaring file) the module's file. A
re-export (`pub use child::Item`, a module's facade) counts only where the module's own code
uses the item. Comments, other strings and `#[cfg(test)]` modules at the end of a file
do not count (a doc link is not an import; `use super::*` in a file's own tests names the file
itself). Prints each circle (with --why, the names each file takes from the others) (a strongly connected set of two or more files) and exits 1 if any
crate has one, 0 otherwise.
"""

import re
import sys
from pathlib import Path

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
PATH_RE = re.compile(rf"\b(?:(crate|super|self)|({IDENT}))((?:::{IDENT})+)")
MOD_DECL = re.compile(rf"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+({IDENT})\s*;", re.M)
# A `mod x;` with the attributes before it (to find a `#[path = "..."]` among them).
MOD_WITH_ATTRS = re.compile(
    rf"((?:#\[[^\]]*\]\s*)*)(?:pub(?:\([^)]*\))?\s+)?\bmod\s+({IDENT})\s*;"
)
PATH_ATTR = re.compile(r'#\[\s*path\s*=\s*"([^"]*)"\s*\]')
# The keys of an attribute whose string value is a Rust path the compiler resolves.
PATH_KEYS = (
    "with", "default", "serialize_with", "deserialize_with", "skip_serializing_if",
    "from", "try_from", "into", "remote", "getter",
)
PATH_VALUE = re.compile(rf"^\s*(?:::)?{IDENT}(?:::{IDENT})*\s*$")
KEY_BEFORE = re.compile(rf"\b({IDENT})\s*=\s*$")


def module_files(src: Path):
    """Module path (tuple) -> file, walking `mod x;` declarations from lib.rs / main.rs."""
    mods = {}

    def visit(path: tuple, file: Path):
        mods[path] = file
        text = strip(file.read_text())
        is_dir_owner = file.name in ("lib.rs", "main.rs", "mod.rs")
        base = file.parent if is_dir_owner else file.parent / file.stem
        for attrs, name in MOD_WITH_ATTRS.findall(text):
            at = PATH_ATTR.search(attrs)
            if at:
                cands = (file.parent / at.group(1),)
            else:
                cands = (base / f"{name}.rs", base / name / "mod.rs")
            for cand in cands:
                if cand.exists():
                    visit(path + (name,), cand)
                    break

    for root in ("lib.rs", "main.rs"):
        if (src / root).exists():
            visit((), src / root)
    return mods


def strip(text: str) -> str:
    """Source without comments and without a trailing `#[cfg(test)]` module; strings are
    emptied but in attributes: a path an attribute names (`with = "crate::a::b"`) is left
    bare, as code (`with = crate::a::b`), and a `#[path = "..."]` keeps its string."""
    text = lex(text)
    m = re.search(r"^#\[cfg\(test\)\]\s*\n\s*mod\s+\w+\s*\{", text, re.M)
    if m:
        text = text[: m.start()]
    return text


def lex(text: str) -> str:
    """One pass over the source: drops comments (line, nested block), empties string and
    char literals, and keeps what attributes say in strings (see `strip`)."""
    out, i, n = [], 0, len(text)
    attr = []  # bracket depth at which each open attribute (`#[`, `#![`) started
    depth = 0
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            level, i = 1, i + 2
            while i < n and level:
                if text.startswith("/*", i):
                    level, i = level + 1, i + 2
                elif text.startswith("*/", i):
                    level, i = level - 1, i + 2
                else:
                    i += 1
        elif c == "r" and re.match(r'r#*"', text[i:]) and not re.match(r"\w", text[i - 1 : i]):
            hashes = re.match(r"r(#*)\"", text[i:]).group(1)
            end = text.find('"' + hashes, i + 2 + len(hashes))
            i = n if end < 0 else end + 1 + len(hashes)
            out.append('""')
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            value = text[i + 1 : j]
            i = j + 1
            out.append(attribute_string(value, "".join(out[-8:]), bool(attr)))
        elif c == "'":
            m = re.match(r"'(?:\\(?:x[0-9a-fA-F]{2}|u\{[0-9a-fA-F]+\}|.)|[^'\\])'", text[i:])
            if m:
                out.append("' '")
                i += m.end()
            else:  # a lifetime or a label
                out.append(c)
                i += 1
        else:
            if c == "#" and re.match(r"#!?\[", text[i:]):
                attr.append(depth)
            elif c == "[":
                depth += 1
            elif c == "]":
                depth -= 1
                if attr and attr[-1] == depth:
                    attr.pop()
            out.append(c)
            i += 1
    return "".join(out)


def attribute_string(value: str, before: str, in_attribute: bool) -> str:
    """What a string literal becomes: a path an attribute names, bare; a `#[path]`'s
    string, kept; any other, empty."""
    key = KEY_BEFORE.search(before)
    if in_attribute and key:
        if key.group(1) == "path":
            return f'"{value}"'
        if key.group(1) in PATH_KEYS and PATH_VALUE.match(value):
            return f" {value.strip()} "
    return '""'


def expand_use(tree: str):
    """Expands a use tree `a::{b, c::{d, e}}` into paths a::b, a::c::d, a::c::e."""
    tree = tree.strip()
    i = tree.find("{")
    if i < 0:
        return [re.sub(r"\s+as\s+\w+$", "", tree).strip()]
    prefix, body = tree[:i], tree[i + 1 : tree.rfind("}")]
    parts, depth, cur = [], 0, ""
    for ch in body:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    parts.append(cur)
    out = []
    for p in parts:
        if p.strip():
            out += [prefix + q for q in expand_use(p)]
    return out


def use_paths(text: str, public: bool):
    """The paths of the `use` declarations (public re-exports, or the others)."""
    out = []
    for m in re.finditer(r"\b(pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", text):
        if bool(m.group(1)) == public:
            out += expand_use(m.group(2))
    return out


def reexports(mods: dict):
    """Module path -> {name it re-exports: the absolute path it names}."""
    out = {}
    for path, file in mods.items():
        text = strip(file.read_text())
        table = {}
        for p in use_paths(text, public=True):
            absolute = absolutise(p, path, set(MOD_DECL.findall(text)))
            if absolute:
                table[absolute[-1]] = absolute
        out[path] = table
    return out


def absolutise(p: str, here: tuple, children: set):
    """The absolute module path of `p` as written in module `here`, if it is in the crate."""
    segs = [s for s in re.sub(r"\s+as\s+\w+$", "", p).replace(" ", "").split("::") if s]
    if not segs:
        return None
    if segs[0] == "crate":
        return tuple(segs[1:])
    if segs[0] in ("super", "self"):
        absolute = here
        while segs and segs[0] in ("super", "self"):
            if segs[0] == "super":
                absolute = absolute[:-1]
            segs = segs[1:]
        return tuple(absolute) + tuple(segs)
    if segs[0] in children:
        return tuple(here) + tuple(segs)
    return None


def resolve(full: tuple, mods: dict, table: dict, depth: int = 0):
    """The file that defines the item at `full`, following re-exports."""
    for k in range(len(full), -1, -1):
        if full[:k] in mods:
            rest = full[k:]
            if rest and depth < 8 and rest[0] in table.get(full[:k], {}):
                target = table[full[:k]][rest[0]] + rest[1:]
                if target != full:
                    return resolve(target, mods, table, depth + 1)
            return mods[full[:k]]
    return None


def imports(file: Path, here: tuple, mods: dict, table: dict):
    text = strip(file.read_text())
    children = set(MOD_DECL.findall(text))
    paths = use_paths(text, public=False)
    body = re.sub(r"\b(?:pub(?:\([^)]*\))?\s+)?use\s+[^;]+;", "", text)
    body = MOD_DECL.sub("", body)
    # A re-export (`pub use child::Item`) is the module's facade; it is a use of the child
    # only where the module's own code names the item too.
    for p in use_paths(text, public=True):
        name = re.sub(r"^.*\s+as\s+", "", p).split("::")[-1].strip()
        if re.search(rf"\b{re.escape(name)}\b", body):
            paths.append(p)
    paths += [m.group(0) for m in PATH_RE.finditer(body)]
    targets = {}
    for p in paths:
        full = absolutise(p, here, children)
        if full is None:
            continue
        t = resolve(full, mods, table)
        if t is not None and t != file:
            targets.setdefault(t, set()).add("::".join(full))
    return targets


def circles(edges: dict):
    """Strongly connected components with two or more files (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in list(edges):
        if v not in index:
            visit(v)
    return out


def main(argv):
    root = Path(__file__).resolve().parent.parent
    why = "--why" in argv
    argv = [a for a in argv if a != "--why"]
    crates = [Path(a) for a in argv] or sorted(p for p in (root / "crates").iterdir() if p.is_dir())
    found = 0
    for crate in crates:
        src = crate / "src"
        mods = module_files(src)
        table = reexports(mods)
        edges = {f: imports(f, path, mods, table) for path, f in mods.items()}
        for comp in circles(edges):
            found += 1
            names = [str(f.relative_to(src)) for f in comp]
            print(f"{crate.name}: circle between {' <-> '.join(names)}")
            if why:
                for f in comp:
                    for t, used in sorted(edges[f].items()):
                        if t in comp:
                            print(f"    {f.relative_to(src)} -> {t.relative_to(src)}: {', '.join(sorted(used))}")
    print(f"{found} import circle(s) in {len(crates)} crate(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
