"""The machine settings editor: machine data, limits, block numbering, line ending, and
the values of the post's options the preview posts with.

The example on the right is the start of the sample program posted with the
settings as they are now, line endings made visible, followed by the limits
the engine checks every move against (a move outside them is an error there).
Options are not saved in the post: they are set when posting (``--option``); here
they choose what the preview shows.
"""

from __future__ import annotations

from typing import Any, ClassVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.screen import ModalScreen
from textual.widgets import Label, Static

from postdsl import api
from tui import edits
from tui.dialogs import focus_now
from tui.document import PostDocument
from tui.fields import Field, FieldForm
from tui.messages import DocumentChanged, DocumentView
from tui.model import format_names, problem_text, setting_at, show_value
from tui.program_view import ProgramView

#: field key -> path in the post (ranges: the path of the [min, max] pair and the index)
PATHS: dict[str, tuple[Any, ...]] = {
    "name": ("machine", "name"),
    "controller": ("machine", "controller"),
    "units": ("machine", "units"),
    "x_min": ("machine", "travel", "x", 0), "x_max": ("machine", "travel", "x", 1),
    "y_min": ("machine", "travel", "y", 0), "y_max": ("machine", "travel", "y", 1),
    "z_min": ("machine", "travel", "z", 0), "z_max": ("machine", "travel", "z", 1),
    "spindle_min": ("machine", "spindle", 0), "spindle_max": ("machine", "spindle", 1),
    "max_feed": ("machine", "max_feed"),
    "rapid_rate": ("machine", "rapid_rate"),
    "max_tool": ("machine", "tools", "max_number"),
    "max_diameter": ("machine", "tools", "max_diameter"),
    "extension": ("output", "extension"),
    "line_ending": ("output", "line_ending"),
    "final_newline": ("output", "final_newline"),
    "n_prefix": ("output", "block_numbers", "prefix"),
    "n_suffix": ("output", "block_numbers", "suffix"),
    "n_start": ("output", "block_numbers", "start"),
    "n_increment": ("output", "block_numbers", "increment"),
    "n_maximum": ("output", "block_numbers", "maximum"),
    "n_format": ("output", "block_numbers", "format"),
    "n_default": ("output", "block_numbers", "default"),
}


def settings_fields(formats: list[str]) -> list[Field]:
    """The form's fields; the block-number format picks from ``formats``."""
    return [
        Field("name", "Machine", help="machine name (required)"),
        Field("controller", "Controller"),
        Field("units", "Units", "choice", ("mm", "inch"), default="mm"),
        Field("x_min", "Travel X min", "number"), Field("x_max", "Travel X max", "number"),
        Field("y_min", "Travel Y min", "number"), Field("y_max", "Travel Y max", "number"),
        Field("z_min", "Travel Z min", "number"), Field("z_max", "Travel Z max", "number"),
        Field("spindle_min", "Spindle min", "number", help="rpm"),
        Field("spindle_max", "Spindle max", "number", help="rpm"),
        Field("max_feed", "Max feed", "number", help="mm/min"),
        Field("rapid_rate", "Rapid rate", "number", default="5000"),
        Field("max_tool", "Max tool no.", "int"),
        Field("max_diameter", "Max tool Ø", "number", help="mm"),
        Field("extension", "Extension", default=".nc"),
        Field("line_ending", "Line ending", "choice", ("lf", "crlf"), default="lf"),
        Field("final_newline", "Final newline", "bool", default="yes"),
        Field("n_prefix", "Number prefix", default="N"),
        Field("n_suffix", "Number suffix", default="' '"),
        Field("n_start", "Number start", "int", default="10"),
        Field("n_increment", "Increment", "int", default="10"),
        Field("n_maximum", "Maximum", "int", default="99999"),
        Field("n_format", "Number format", "choice", tuple(formats), default="integer"),
        Field("n_default", "Number blocks", "bool", default="yes"),
    ]


#: the field keys of options: "option-" and the option's name
OPTION_FIELD = "option-"


def option_fields(post: api.Post) -> list[Field]:
    """A field per option of the post, its default shown, its description as help."""
    fields = []
    for option in post.options.values():
        kind = {"bool": "bool", "int": "int", "number": "number"}.get(option.type, "text")
        choices: tuple[str, ...] = ()
        if option.choices is not None:
            kind, choices = "choice", tuple(str(c) for c in option.choices)
        about = "option (not saved: the preview's value)"
        fields.append(Field(OPTION_FIELD + option.name, option.name, kind,
                            choices, default=show_value(option.default),
                            help=f"{about}: {option.description}" if option.description
                            else about))
    return fields


class SettingsEditor(DocumentView, ModalScreen[None]):
    """Machine data and output settings, committed field by field (each one undoable)."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "close", "Close"),
        # the options come after the 25 settings: one key, not 25 tabs
        Binding("ctrl+o", "options", "Options"),
    ]

    def __init__(self, doc: PostDocument, program: ProgramView) -> None:
        super().__init__()
        self.doc = doc
        #: the main screen's program view: the example is the start of the sample program
        self.program = program

    def compose(self) -> ComposeResult:
        with Vertical(id="settings-editor", classes="dialog full"):
            yield Label("Machine and output settings", classes="dialog-title")
            with Horizontal(id="settings-body"):
                yield FieldForm(settings_fields(format_names(self.doc.model))
                                + option_fields(self.doc.model), id="settings-form")
                with VerticalScroll(id="settings-side"):
                    yield Static("", id="settings-example")
            yield Static("tab: next field · enter: apply · ctrl+o: options (the preview's "
                         "values, not saved) · ctrl+z: undo · escape: close",
                         classes="dialog-hint")

    def on_mount(self) -> None:
        self.document_changed()
        focus_now(self.query_one("#f-name"))

    def document_changed(self) -> None:
        """Show the post's settings again (after an edit, undo or redo)."""
        model = self.doc.model
        values = {key: setting_at(model, path) for key, path in PATHS.items()}
        for name, value in self.doc.options.items():
            option = model.options.get(name)
            values[OPTION_FIELD + name] = str(value) if option is not None and \
                option.choices is not None else value
        self.query_one(FieldForm).load(values)
        self._show_example()

    def _show_example(self) -> None:
        doc = self.doc
        model = doc.model
        text = Text()
        text.append("Start of the sample program\n", style="bold")
        ending = " CR↵" if setting_at(model, ("output", "line_ending")) == "crlf" else "↵"
        lines, error = self.program.lines, self.program.message or None
        prefix = str(setting_at(model, ("output", "block_numbers", "prefix")) or "N")
        first = next((i for i, line in enumerate(lines) if line.startswith(prefix)), 0)
        for line in lines[first:first + 8]:
            text.append(line)
            text.append(f"{ending}\n", style="dim")
        if doc.post is None:
            text.append("the post has problems:\n", style="bold red")
            for problem in doc.problems[:5]:
                text.append(f"  {problem_text(problem)}\n", style="red")
        elif error:
            text.append(f"{error}\n", style="bold red")
        final = setting_at(model, ("output", "final_newline")) is not False
        text.append(f"\nthe file {'ends' if final else 'does not end'} with a line break\n",
                    style="dim")
        text.append("\nLimits checked on every move\n", style="bold")
        for axis in "xyz":
            limits = setting_at(model, ("machine", "travel", axis))
            if limits:
                text.append(f"  {axis.upper()} {show_value(limits[0])} … "
                            f"{show_value(limits[1])} mm\n")
        spindle = setting_at(model, ("machine", "spindle"))
        if spindle:
            text.append(f"  spindle {show_value(spindle[0])} … {show_value(spindle[1])} rpm\n")
        feed = setting_at(model, ("machine", "max_feed"))
        if feed is not None:
            text.append(f"  feed up to {show_value(feed)} mm/min\n")
        self.query_one("#settings-example", Static).update(text)

    @on(FieldForm.Committed)
    def _committed(self, event: FieldForm.Committed) -> None:
        event.stop()
        key, value = event.field.key, event.value
        if key.startswith(OPTION_FIELD):
            self._set_option(key[len(OPTION_FIELD):], value)
            return
        path = PATHS[key]
        form = self.query_one(FieldForm)
        if isinstance(path[-1], int):  # one end of a [min, max] range
            pair_path = path[:-1]
            other_key = key[:-3] + ("max" if key.endswith("min") else "min")
            other = form.values().get(other_key)
            low, high = (value, other) if path[-1] == 0 else (other, value)
            if low is None and high is None:
                self.change(f"setting {key}", lambda data: edits.set_value(
                    data, pair_path, None))
                return
            if low is None or high is None:
                form.error(key, "give both ends of the range")
                return
            existing = setting_at(self.doc.model, pair_path)
            if isinstance(existing, list) and len(existing) == 2:
                self.change(f"setting {key}", lambda data: edits.set_value(
                    data, path, value))
            else:
                self.change(f"setting {key}", lambda data: edits.set_value(
                    data, pair_path, edits.flow_seq([low, high])))
            return
        self.change(f"setting {key}", lambda data: edits.set_value(data, path, value))

    @on(FieldForm.Edited)
    def _edited(self, event: FieldForm.Edited) -> None:
        event.stop()

    def _set_option(self, name: str, value: Any) -> None:
        """The preview posts with this option value from now on (None: the default)."""
        options = {k: v for k, v in self.doc.options.items() if k != name}
        if value is not None:
            options[name] = value
        self.doc.set_options(options)
        problems = [p for p in self.doc.problems if "option" in p.message]
        if problems:
            self.query_one(FieldForm).error(OPTION_FIELD + name, problems[0].message)
        self.post_message(DocumentChanged(f"option {name}"))

    def action_options(self) -> None:
        """The first option's field (the post's options follow its settings)."""
        fields = [f for f in self.query_one(FieldForm).fields if f.startswith(OPTION_FIELD)]
        if not fields:
            self.notify("this post has no options", severity="information")
            return
        self.query_one(f"#f-{fields[0]}").focus()

    def action_close(self) -> None:
        self.dismiss(None)
