"""The one walker: a schema-valid post document -> the typed model of :mod:`nodes`.

Only this module (and the loader's schema step, and the editor's edit writer, which
change the round-trip document by path) reads a post document by key.  It runs after
the JSON Schema has accepted the document, so every value has the type the schema
states; what a schema cannot say (names, expressions, ranges) is left to the checks,
which read the model.  Expressions are compiled here, once, against the names known
where they stand; one that does not compile keeps its error for the checks to report.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from postdsl.cl.model import PARAMETERS, with_previous
from postdsl.lang.expr import ExprError, compile_expr
from postdsl.lang.formats import NumberFormat
from postdsl.lang.post import nodes as n

PathKey = tuple[Any, ...]

#: the keys of ``output.block_numbers``, each a setting that may be ``{option: NAME}``
_NUMBER_KEYS = ("prefix", "suffix", "start", "increment", "maximum", "wrap", "format",
                "default")


def plain(value: Any) -> Any:
    """ruamel scalars -> plain Python values (so they compare and hash as users expect)."""
    if isinstance(value, bool) or value is None:
        return value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        return float(value)
    if isinstance(value, str):
        return str(value)
    if isinstance(value, Mapping):
        return {plain(k): plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [plain(v) for v in value]
    return value


def known_names(data: Mapping[str, Any]) -> frozenset[str]:
    """The names an expression of the post may read: parameters, variables, flags and
    options, and the ``prev_`` name of each (of a document that may not be valid: what is
    not a mapping names nothing)."""
    names = set(PARAMETERS)
    for key in ("variables", "flags", "options"):
        section = data.get(key) if isinstance(data, Mapping) else None
        names |= {str(k) for k in section} if isinstance(section, Mapping) else set()
    return with_previous(names)


def structure_parameters(data: Mapping[str, Any]) -> dict[str, frozenset[str]]:
    """Each structure's parameters: the names its ``use:`` sites give with ``with:`` (of a
    document that may not be valid: what is not a use: block gives none)."""
    tables: list[Any] = []
    for key in ("commands", "custom_cycles"):
        section = data.get(key) if isinstance(data, Mapping) else None
        tables += [table.get("blocks") for table in section.values()
                   if isinstance(table, Mapping)] if isinstance(section, Mapping) else []
    structures = data.get("structures") if isinstance(data, Mapping) else None
    tables += list(structures.values()) if isinstance(structures, Mapping) else []
    found: dict[str, set[str]] = {}
    for blocks in tables:
        for block in blocks if isinstance(blocks, list) else ():
            if isinstance(block, Mapping) and isinstance(block.get("use"), str):
                names = found.setdefault(str(block["use"]), set())
                bindings = block.get("with")
                if isinstance(bindings, Mapping):
                    names.update(str(name) for name in bindings)
    return {name: frozenset(names) for name, names in found.items()}


def format_stand_ins(data: Mapping[str, Any]) -> dict[str, NumberFormat]:
    """A format for each name the post defines, for checking ``str(x, 'name')``.

    What a format writes may depend on options, known only when the post is compiled;
    the compiler compiles every expression that uses ``str()`` again with the real ones.
    """
    section = data.get("formats") if isinstance(data, Mapping) else None
    return {str(name): NumberFormat() for name in section} if isinstance(section, Mapping) \
        else {}


def build_post(data: Mapping[str, Any], file: str, *, lenient: bool = False,
               origin: str | None = None, names: frozenset[str] = frozenset()) -> n.Post:
    """The model of a schema-valid post document ``data`` read from ``file``.

    ``lenient`` builds what it can of a document the schema has not accepted (the
    editor's, between two edits): a table, block or item of the wrong shape is left
    out (an item becomes empty fixed text, so positions stay those of the document).
    ``origin`` marks every node as written in that file (a base of another post);
    ``names`` are known to expressions besides the document's own (the variables and
    options of the other posts of an ``extends:`` chain).
    """
    if lenient:
        return _LenientBuilder(file, origin, names).post(data if isinstance(data, Mapping)
                                                         else {})
    return _Builder(file, origin, names).post(data)


def build_item(value: Any, path: PathKey = ()) -> n.Item:
    """One item (a YAML string or mapping), as the editor's clipboard holds it."""
    return _LenientBuilder("<item>").item(path, value, known_names({}))


#: what a value of the wrong shape raises while it is read as the schema says
_SHAPE_ERRORS = (AttributeError, KeyError, TypeError, ValueError, IndexError)


class _Builder:
    def __init__(self, file: str, origin: str | None = None,
                 names: frozenset[str] = frozenset()) -> None:
        self.file = file
        #: the file nodes are marked with (None: the post's own)
        self.origin = origin
        self.names = names
        #: the formats ``str(x, 'name')`` may name (stand-ins: see format_stand_ins)
        self.formats: dict[str, NumberFormat] = {}

    def section(self, data: Mapping[str, Any], key: str) -> list[tuple[str, Any]]:
        """The (name, value) pairs of a top-level mapping such as ``commands``."""
        return [(str(k), v) for k, v in (data.get(key) or {}).items()]

    def post(self, data: Mapping[str, Any]) -> n.Post:
        names = known_names(data) | self.names
        self.formats = {**format_stand_ins(data), **self.formats}
        cycles = self.section(data, "custom_cycles")
        cycle_params = with_previous(str(p) for _, c in cycles
                                     for p in self.mapping(c, "parameters"))
        parameters = structure_parameters(data)
        machine = data.get("machine")
        output = data.get("output")
        return n.Post(
            file=self.file,
            version=data.get("postdsl"),
            extends=plain(data.get("extends")),
            machine=self.machine(machine) if machine is not None else None,
            output=self.output(output) if output is not None else None,
            formats={str(k): n.FormatSpec(("formats", k), str(k),
                                          {str(key): self.setting(("formats", k, key), value)
                                           for key, value in (v or {}).items()}, self.origin)
                     for k, v in self.section(data, "formats")},
            variables={str(k): n.Variable(("variables", k), str(k), plain(v), self.origin)
                       for k, v in self.section(data, "variables")},
            flags={str(k): n.Flag(("flags", k), str(k), plain(v), self.origin)
                   for k, v in self.section(data, "flags")},
            options={str(k): self.option(("options", k), str(k), v)
                     for k, v in self.section(data, "options")},
            structures={str(k): n.Structure(("structures", k), str(k),
                                            self.blocks(("structures", k), v,
                                                        names | cycle_params
                                                        | parameters.get(str(k), frozenset())),
                                            self.origin)
                        for k, v in self.section(data, "structures")},
            commands={str(k): self.command(("commands", k), str(k), v, names)
                      for k, v in self.section(data, "commands")},
            custom_cycles={str(k): self.cycle(("custom_cycles", k), str(k), v, names)
                           for k, v in cycles},
        )

    def mapping(self, node: Any, key: str) -> Mapping[str, Any]:
        return node.get(key) or {}

    # --- settings -------------------------------------------------------------------------

    def setting(self, path: PathKey, value: Any) -> Any:
        """A plain value, or an :class:`~nodes.OptionRef` for ``{option: name}``."""
        if isinstance(value, Mapping) and "option" in value:
            return n.OptionRef(path, str(value["option"]), self.origin)
        return plain(value)

    def option(self, path: PathKey, name: str, spec: Mapping[str, Any]) -> n.Option:
        choices = spec.get("choices")
        return n.Option(path, name, str(spec["type"]), plain(spec.get("default")),
                        tuple(plain(c) for c in choices) if choices is not None else None,
                        str(spec.get("description", "")), self.origin)

    def machine(self, spec: Mapping[str, Any]) -> n.MachineSpec:
        tools = spec.get("tools")
        spindle = spec.get("spindle")
        return n.MachineSpec(
            path=("machine",),
            name=str(spec["name"]),
            controller=plain(spec.get("controller")),
            control=plain(spec.get("control")),
            resolution=plain(spec.get("resolution")),
            calculator_input=plain(spec.get("calculator_input")),
            units=plain(spec.get("units")),
            travel={str(axis): (plain(r[0]), plain(r[1]))
                    for axis, r in (spec.get("travel") or {}).items()},
            spindle=(plain(spindle[0]), plain(spindle[1])) if spindle is not None else None,
            min_feed=plain(spec.get("min_feed")),
            max_feed=plain(spec.get("max_feed")),
            rapid_rate=self.setting(("machine", "rapid_rate"), spec.get("rapid_rate")),
            tool_changer=plain(spec.get("tool_changer")),
            tools=n.Tools(("machine", "tools"), plain(tools.get("min_number")),
                          plain(tools.get("max_number")), plain(tools.get("max_diameter")))
            if tools is not None else None,
            file=self.origin,
            tilted_plane=plain(spec.get("tilted_plane")),
            cutter_compensation=self.setting(("machine", "cutter_compensation"),
                                             spec.get("cutter_compensation")),
        )

    def output(self, spec: Mapping[str, Any]) -> n.Output:
        numbers = spec.get("block_numbers")
        here = ("output", "block_numbers")
        return n.Output(
            path=("output",),
            extension=plain(spec.get("extension")),
            line_ending=plain(spec.get("line_ending")),
            final_newline=plain(spec.get("final_newline")),
            motion_register=plain(spec.get("motion_register")),
            word_separator=plain(spec.get("word_separator")),
            trim_line_ends=plain(spec.get("trim_line_ends")),
            block_numbers=n.BlockNumbers(here, **{
                key: self.setting(here + (key,), numbers[key]) for key in _NUMBER_KEYS
                if key in numbers}) if numbers is not None else None,
        )

    # --- tables ---------------------------------------------------------------------------

    def expr(self, path: PathKey, source: Any, names: frozenset[str]) -> n.Expr:
        text = str(source)
        try:
            return n.Expr(path, text, compile_expr(text, names, self.formats), None,
                          self.origin)
        except ExprError as exc:
            return n.Expr(path, text, None, exc, self.origin)

    def table_fields(self, path: PathKey, name: str, spec: Mapping[str, Any],
                     names: frozenset[str]) -> dict[str, Any]:
        blocks = spec.get("blocks")
        preview = spec.get("preview")
        assume = spec.get("assume")
        reset = spec.get("reset")
        reject = spec.get("reject")
        verify = spec.get("verify")
        sets = spec.get("set")
        return dict(
            path=path, name=name,
            blocks=self.blocks(path + ("blocks",), blocks, names) if blocks is not None
            else None,
            doc=plain(spec.get("doc")),
            preview={str(k): plain(v) for k, v in preview.items()} if preview is not None
            else None,
            assume={str(k): self.expr(path + ("assume", k), v, names)
                    for k, v in assume.items()} if assume is not None else None,
            reset=tuple(str(r) for r in reset) if reset is not None else None,
            reject=tuple(n.Reject(path + ("reject", i),
                                  self.expr(path + ("reject", i, "if"), rule["if"], names),
                                  str(rule["message"]))
                         for i, rule in enumerate(reject)) if reject is not None else None,
            verify=n.Verify(path + ("verify",), plain(verify.get("motion")),
                            tuple(str(w) for w in verify["words"]) if "words" in verify
                            else None) if verify is not None else None,
            file=self.origin,
            sets={str(k): self.expr(path + ("set", k), v, names) for k, v in sets.items()}
            if sets is not None else None,
        )

    def command(self, path: PathKey, name: str, spec: Mapping[str, Any],
                names: frozenset[str]) -> n.Command:
        new_cycle = spec.get("new_cycle_if")
        expand_if = spec.get("expand_if")
        return n.Command(
            **self.table_fields(path, name, spec, names),
            redirect=plain(spec.get("redirect")),
            new_cycle_if=self.expr(path + ("new_cycle_if",), new_cycle, names)
            if new_cycle is not None else None,
            expand=plain(spec.get("expand")),
            expand_if=self.expr(path + ("expand_if",), expand_if, names)
            if expand_if is not None else None,
            tolerance=plain(spec.get("tolerance")),
        )

    def cycle(self, path: PathKey, name: str, spec: Mapping[str, Any],
              names: frozenset[str]) -> n.CustomCycle:
        parameters = spec.get("parameters")
        params = {str(p): n.CycleParameter(path + ("parameters", p), str(p),
                                           plain((s or {}).get("default")),
                                           plain((s or {}).get("doc")))
                  for p, s in (parameters or {}).items()}
        return n.CustomCycle(**self.table_fields(path, name, spec, names | frozenset(params)),
                             parameters=params if parameters is not None else None)

    def blocks(self, path: PathKey, blocks: Any, names: frozenset[str]) \
            -> tuple[n.BlockEntry, ...]:
        return tuple(self.block(path + (index,), block, names)
                     for index, block in enumerate(blocks or ()))

    def block(self, here: PathKey, block: Any, names: frozenset[str]) -> n.BlockEntry:
        if "use" in block:
            condition, bindings = block.get("if"), block.get("with")
            return n.Use(here, str(block["use"]), self.origin,
                         condition=self.expr(here + ("if",), condition, names)
                         if condition is not None else None,
                         bindings={str(k): self.expr(here + ("with", k), v, names)
                                   for k, v in bindings.items()}
                         if bindings is not None else None)
        condition = block.get("if")
        return n.Block(
            path=here,
            items=tuple(self.item(here + ("items", i), item, names)
                        for i, item in enumerate(block["items"])),
            condition=self.expr(here + ("if",), condition, names)
            if condition is not None else None,
            number=plain(block.get("number")),
            renumber=plain(block.get("renumber")),
            for_each=plain(block.get("for_each")),
            only_with_values=plain(block.get("only_with_values")),
            file=self.origin,
        )

    def item(self, path: PathKey, item: Any, names: frozenset[str]) -> n.Item:
        if isinstance(item, str):
            return n.PlainText(path, file=self.origin, text=str(item))
        condition, force, replace = item.get("if"), item.get("force_if"), item.get("replace")
        common = dict(
            path=path,
            prefix=plain(item.get("prefix")),
            suffix=plain(item.get("suffix")),
            format=plain(item.get("format")),
            mode=plain(item.get("mode")),
            modal=plain(item.get("modal")),
            condition=self.expr(path + ("if",), condition, names)
            if condition is not None else None,
            force_if=self.expr(path + ("force_if",), force, names)
            if force is not None else None,
            replace=tuple((str(old), str(new)) for old, new in replace.items())
            if replace is not None else None,
            file=self.origin,
        )
        if "text" in item:
            return n.TextItem(**common, text=str(item["text"]))
        if "param" in item:
            return n.ParamItem(**common, param=str(item["param"]))
        return n.ExprItem(**common, expr=self.expr(path + ("expr",), item["expr"], names))


class _LenientBuilder(_Builder):
    """The builder for a document the schema has not accepted: what does not fit is
    left out rather than raised."""

    def section(self, data: Mapping[str, Any], key: str) -> list[tuple[str, Any]]:
        node = data.get(key)
        return [(str(k), v) for k, v in node.items()] if isinstance(node, Mapping) else []

    def mapping(self, node: Any, key: str) -> Mapping[str, Any]:
        value = node.get(key) if isinstance(node, Mapping) else None
        return value if isinstance(value, Mapping) else {}

    def post(self, data: Mapping[str, Any]) -> n.Post:
        post = super().post(data)
        keep = {name: node for name, node in post.structures.items() if node is not None}
        commands = {name: node for name, node in post.commands.items() if node is not None}
        cycles = {name: node for name, node in post.custom_cycles.items() if node is not None}
        return n.Post(file=post.file, version=post.version, extends=post.extends,
                      machine=post.machine, output=post.output, formats=post.formats,
                      variables=post.variables, flags=post.flags, options=post.options,
                      structures=keep,
                      commands=commands, custom_cycles=cycles)

    def machine(self, spec: Mapping[str, Any]) -> n.MachineSpec:
        try:
            return super().machine(spec)
        except _SHAPE_ERRORS:
            return None  # type: ignore[return-value]  # a shape error: the checks report it

    def output(self, spec: Mapping[str, Any]) -> n.Output:
        try:
            return super().output(spec)
        except _SHAPE_ERRORS:
            return None  # type: ignore[return-value]  # a shape error: the checks report it

    def option(self, path: PathKey, name: str, spec: Mapping[str, Any]) -> n.Option:
        try:
            return super().option(path, name, spec)
        except _SHAPE_ERRORS:
            return n.Option(path, name, "string", None, file=self.origin)

    def command(self, path: PathKey, name: str, spec: Mapping[str, Any],
                names: frozenset[str]) -> n.Command:
        try:
            return super().command(path, name, spec, names)
        except _SHAPE_ERRORS:
            return n.Command(path, name, file=self.origin)

    def cycle(self, path: PathKey, name: str, spec: Mapping[str, Any],
              names: frozenset[str]) -> n.CustomCycle:
        try:
            return super().cycle(path, name, spec, names)
        except _SHAPE_ERRORS:
            return n.CustomCycle(path, name, file=self.origin)

    def blocks(self, path: PathKey, blocks: Any, names: frozenset[str]) \
            -> tuple[n.BlockEntry, ...]:
        return super().blocks(path, blocks if isinstance(blocks, list) else (), names)

    def block(self, here: PathKey, block: Any, names: frozenset[str]) -> n.BlockEntry:
        try:
            return super().block(here, block, names)
        except _SHAPE_ERRORS:
            return n.Block(here, (), file=self.origin)

    def item(self, path: PathKey, item: Any, names: frozenset[str]) -> n.Item:
        try:
            return super().item(path, item, names)
        except _SHAPE_ERRORS:
            return n.PlainText(path, file=self.origin, text="")

    def expr(self, path: PathKey, source: Any, names: frozenset[str]) -> n.Expr:
        if not isinstance(source, str):
            return n.Expr(path, "", None, ExprError("not an expression", 0), self.origin)
        return super().expr(path, source, names)

