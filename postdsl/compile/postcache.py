"""Keep checked posts between runs, so ``postdsl post`` neither parses nor checks again.

Reading a post is most of the fixed cost of posting a short program: the YAML parse
(ruamel, round-trip), the schema, the semantic checks, and the imports of ruamel and
jsonschema themselves.  A shop posts many programs with one post, so the result of
:func:`postdsl.lang.loader.check` — the :class:`~postdsl.lang.loader.CheckedPost` — is kept in
the folder of :mod:`postdsl.codecache` (``$POSTDSL_CACHE_DIR``, else the user's cache),
an entry ``KEY.post`` beside the ``KEY.code`` entries, with the same header, checks and
atomic writes.

What an entry depends on, and how a stale one is never used:

- its name (the key) hashes the post's text, its path as given and resolved, the
  bundled machines folder, the schema's text, and :func:`postdsl.codecache.environment`:
  a digest of postdsl's source (a changed checker or builder must not meet an old
  entry, and ``__version__`` does not change with the code), the versions of ruamel.yaml
  and jsonschema (they decide what a post's text means and whether it passes), and
  Python's;
- the entry records each base the post ``extends`` (by the path it was read from,
  and the hash of its text) and each ``extends:`` name with the file it resolved to;
  an entry is used only when every base still has that text and every name still
  resolves to the same file (a base added in ``machines/bases`` shadows a bundled post);
- option values are not part of it: options are applied to the checked post when it
  is compiled, on every run, so one entry serves every set of option values.

A post with any problem raises before anything is written: a bad post is never in
the cache, and its messages are made by the same code as without one.  The post's
YAML document is not in the entry: a post from the cache parses its text only when a
message needs a line and column (:class:`_ParsedOnDemand`), so every message is the
same as for a freshly read post.

Why loading an entry is safe: entries are written by postdsl alone, into the user's
own cache folder, after the post passed every check; an entry is read only when it is
a regular file of the user's that no one else may write
(:func:`postdsl.codecache.trusted`); the header holds the key and the
SHA-256 of the payload, so a torn, truncated or foreign file is ignored and the post
read again.  The payload is a pickle, read by an unpickler that resolves only
the classes of postdsl's post model (:data:`_MODEL_MODULES`) and a few plain types
(:data:`_PLAIN`), never a function other than the rebuilders of this module: even an
altered entry can build postdsl's model objects, not call arbitrary code.  Compiled
expressions hold closures, which are not pickled: the entry holds their checked syntax
tree, and loading compiles the tree again with the same compiler (no text is parsed).
"""

from __future__ import annotations

import hashlib
import io
import pickle
from collections.abc import Iterable
from pathlib import Path, PurePath
from typing import Any

from postdsl.codecache import cache_dir, environment, read_entry, write_entry
from postdsl.lang.expr.compiler import Compiler, Expression
from postdsl.lang.loader import CheckedPost, PostSource, check, parse_yaml, read_source
from postdsl.resources import machines_dir, schema_path
from postdsl.textfile import TextFileError, read_text

_MAGIC = b"postdsl-post-1\n"

#: the modules of postdsl whose classes make up a checked post (plain data, no effects)
_MODEL_MODULES = frozenset({"postdsl.lang.post.nodes", "postdsl.lang.expr.nodes",
                            "postdsl.lang.expr.errors", "postdsl.lang.formats",
                            "postdsl.lang.loader", "postdsl.errors"})

#: the classes outside postdsl an entry may hold (besides what pickle writes natively)
_PLAIN = {("builtins", "frozenset"), ("builtins", "set"), ("builtins", "complex"),
          ("pathlib", "PosixPath"), ("pathlib", "WindowsPath"), ("pathlib", "Path")}


def load_checked(path: Path) -> CheckedPost:
    """The checked post of the file at ``path``: from the cache when a sound entry is
    there, else read and checked (and then kept).  Raises PostError as
    ``check(read_source(path))`` does."""
    folder = cache_dir()
    if folder is None:
        return check(read_source(path))
    try:
        text = read_text(path)
    except (OSError, TextFileError):
        return check(read_source(path))  # read_source words the error
    key = _key(path, text)
    entry = folder / f"{key}.post"
    payload = read_entry(entry, _MAGIC, key)
    if payload is not None:
        cached = _loads(payload)
        if cached is not None and _current(cached[0], cached[1]):
            checked = cached[2]
            if isinstance(checked, CheckedPost) and checked.source.text == text:
                return checked
    source = read_source(path)
    checked = check(source)
    if source.text == text:  # the file did not change while it was read
        _store(entry, key, checked)
    return checked


# --- the key and the bases ---------------------------------------------------------------------


def _key(path: Path, text: str) -> str:
    digest = hashlib.sha256()
    for part in (environment(), _schema_text(), str(machines_dir()), str(path),
                 _resolved(path), text):
        digest.update(part.encode("utf-8", "surrogatepass"))
        digest.update(b"\0")
    return digest.hexdigest()


def _resolved(path: Path) -> str:
    try:
        return str(path.resolve())
    except (OSError, RuntimeError):
        return str(path.absolute())


def _schema_text() -> str:
    try:
        return schema_path("post.schema.json").read_text(encoding="utf-8")
    except OSError:
        return ""


def _text_hash(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()


Bases = list[tuple[str, str]]
Links = list[tuple[str, "str | None", str]]


def _dependencies(checked: CheckedPost) -> tuple[Bases, Links]:
    """(base file, hash of its text) of every base, and (``extends:`` name, the file
    that names it, the file it resolved to) of every link of the chain."""
    from postdsl.lang.post.extends import extends_of  # writing an entry only

    bases: Bases = []
    links: Links = []
    child = checked.source
    for base in checked.bases.values():  # nearest first, as the chain was read
        name = extends_of(child.data)
        if name is None or base.path is None:
            raise ValueError("a chain without its files")  # not kept: never seen so far
        bases.append((str(base.path), _text_hash(base.text)))
        links.append((name, str(child.path) if child.path is not None else None,
                      str(base.path)))
        child = base
    return bases, links


def _current(bases: Bases, links: Links) -> bool:
    """Whether every base still has its text and every name still finds the same file."""
    if not links and not bases:
        return True
    from postdsl.lang.post.extends import base_file  # only a post that extends another

    machines = machines_dir()
    for name, child, found in links:
        now = base_file(name, Path(child) if child is not None else None, machines)
        if now is None or str(now) != found:
            return False
    for file, digest in bases:
        try:
            if _text_hash(read_text(file)) != digest:
                return False
        except (OSError, TextFileError):
            return False
    return True


# --- the entry -------------------------------------------------------------------------------


def _store(entry: Path, key: str, checked: CheckedPost) -> None:
    try:
        bases, links = _dependencies(checked)
        buffer = io.BytesIO()
        _Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL).dump((bases, links, checked))
    except (pickle.PicklingError, TypeError, AttributeError, ValueError, RecursionError):
        return  # something of the post cannot be kept: it is read each time, as before
    write_entry(entry, _MAGIC, key, buffer.getvalue())


def _loads(payload: bytes) -> tuple[Bases, Links, Any] | None:
    try:
        value = _Unpickler(io.BytesIO(payload)).load()
    except Exception:  # an entry of another postdsl, or altered: read the post again
        return None
    if not (isinstance(value, tuple) and len(value) == 3 and isinstance(value[0], list)
            and isinstance(value[1], list)):
        return None
    return value


class _Pickler(pickle.Pickler):
    """Keeps a post's sources as text and its expressions as syntax trees."""

    def reducer_override(self, obj: Any) -> Any:
        if isinstance(obj, PostSource):
            return _ParsedOnDemand, (obj.file, None, obj.text, obj.path)
        if type(obj) is Expression:
            return _expression, (obj.source, obj.names, obj.tree, dict(obj.formats),
                                 obj.texts)
        module = type(obj).__module__
        if module.startswith("ruamel"):  # a value the builder left as ruamel's own
            return _plain(obj)
        return NotImplemented


def _plain(obj: Any) -> Any:
    """A ruamel value as the plain value it stands for (pickle reduces what this returns)."""
    if isinstance(obj, bool):
        return bool, (bool(obj),)
    for kind in (int, float, str):
        if isinstance(obj, kind):
            return kind, (kind(obj),)
    if isinstance(obj, dict):
        return _as_dict, (list(obj.items()),)
    if isinstance(obj, list):
        return list, (list(obj),)
    raise pickle.PicklingError(f"a {type(obj).__name__} in a post")


def _as_dict(items: Iterable[tuple[Any, Any]]) -> dict[Any, Any]:
    return dict(items)


class _Unpickler(pickle.Unpickler):
    def find_class(self, module: str, name: str) -> Any:
        if (module, name) in _PLAIN:
            return super().find_class(module, name)
        if module == __name__ and name in ("_ParsedOnDemand", "_expression", "_as_dict"):
            return super().find_class(module, name)
        if module in _MODEL_MODULES:
            found = super().find_class(module, name)
            if isinstance(found, type):
                return found
        raise pickle.UnpicklingError(f"{module}.{name} is not allowed in a post entry")


def _expression(source: str, names: frozenset[str], tree: Any, formats: dict[str, Any],
                texts: frozenset[str]) -> Expression:
    """An expression compiled again from its checked tree, as ``compile_expr`` made it."""
    code = Compiler(source, formats).compile(tree)
    return Expression(source=source, names=names, evaluate=code.run, tree=tree,
                      formats=formats, texts=texts)


class _ParsedOnDemand(PostSource):
    """A post source from the cache: its text, its YAML document parsed when first asked
    for (a message's line and column, an editor), so posting never parses."""

    def __init__(self, file: str, data: Any = None, text: str = "",
                 path: PurePath | None = None) -> None:
        # the dataclass's fields (dataclasses.replace works), but ``data`` is a property
        self.file = file
        self.text = text
        self.path = Path(path) if path is not None else None
        self._document: Any = data

    @property
    def data(self) -> Any:
        if self._document is None:
            self._document = parse_yaml(self.text, self.file)
        return self._document

    @data.setter
    def data(self, value: Any) -> None:
        self._document = value
