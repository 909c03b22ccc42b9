"""Generate ``schemas/cl.schema.json`` and ``docs/cl-format.md`` from the CL vocabulary.

The schema documents the native format for other tools (a CAM exporter can
validate its output with any JSON Schema library).  It is generated so it can
never drift from the model; ``python -m postdsl.cl.schema`` rewrites both files
and a test fails when a committed one is stale.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

from postdsl.cl.model import COMMAND_TYPES, GROUPS, command_fields, field_type


def _field_schema(f: Any) -> dict[str, Any]:
    kind, optional = field_type(f)
    if kind == "object":
        schema: dict[str, Any] = {
            "type": "object",
            "additionalProperties": {"type": ["number", "string"]},
        }
    elif kind == "text":
        schema = {"type": "string"}
        if f.metadata["choices"]:
            schema["enum"] = list(f.metadata["choices"])
    else:
        schema = {"type": kind}
    if optional:
        schema["type"] = [schema["type"], "null"]
    description = f.metadata["doc"]
    if f.metadata["unit"]:
        description += f" [{f.metadata['unit']}]"
    schema["description"] = description
    return schema


def build_schema() -> dict[str, Any]:
    """The JSON Schema of one native CL record."""
    variants = []
    for cls in COMMAND_TYPES:
        properties: dict[str, Any] = {"cmd": {"const": cls.name}}
        for f in command_fields(cls):
            properties[f.name] = _field_schema(f)
        variants.append({
            "title": cls.name,
            "description": cls.doc,
            "type": "object",
            "properties": properties,
            "required": ["cmd"],
            "additionalProperties": False,
            "examples": [cls.example],
        })
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://postdsl.dev/schemas/cl.schema.json",
        "title": "postdsl native CL record (one JSON object per line)",
        "description": "Generated from postdsl/cl/model.py by `python -m postdsl.cl.schema`.",
        "oneOf": variants,
    }


def render_schema() -> str:
    return json.dumps(build_schema(), indent=2, ensure_ascii=False) + "\n"


def render_reference() -> str:
    """The native format's reference page: every command, its fields and an example."""
    out = [
        "# Native CL format: command reference",
        "",
        "Generated from `postdsl/cl/model.py` by `python -m postdsl.cl.schema`; do not edit.",
        "",
        "One JSON object per line; `cmd` names the command, the other keys are its fields.",
        "Lines starting with `#` and blank lines are skipped.  Lengths are mm, feeds mm/min,",
        "times s.  A field left out takes its default; a *sticky* field left out keeps the",
        "value it had (an axis not named in a move has not moved).",
        "",
    ]
    for group in GROUPS:
        members = [cls for cls in COMMAND_TYPES if cls.group == group]
        if not members:
            continue
        out += [f"## {group.capitalize()}", ""]
        for cls in members:
            out += [f"### `{cls.name}`", "", cls.doc, ""]
            fields = command_fields(cls)
            if fields:
                out += ["| field | type | default | meaning |", "| --- | --- | --- | --- |"]
                for f in fields:
                    kind = _field_schema(f)["type"]
                    kind = " or ".join(kind) if isinstance(kind, list) else kind
                    choices = f.metadata["choices"]
                    if choices:
                        kind += ": " + ", ".join(f"`{c}`" for c in choices)
                    default = "—" if f.default is dataclasses.MISSING else f"`{f.default!r}`"
                    meaning = f.metadata["doc"] + (f" [{f.metadata['unit']}]"
                                                   if f.metadata["unit"] else "")
                    if f.metadata["sticky"]:
                        meaning += " (sticky)"
                    out.append(f"| `{f.name}` | {kind} | {default} | {meaning} |")
                out.append("")
            out += ["```json", json.dumps(cls.example, ensure_ascii=False), "```", ""]
    return "\n".join(out)


def main() -> None:
    root = Path(__file__).resolve().parents[2]
    targets = {root / "schemas" / "cl.schema.json": render_schema(),
               root / "docs" / "cl-format.md": render_reference()}
    for target, text in targets.items():
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
        print(f"wrote {target}")


if __name__ == "__main__":
    main()
