"""Generate ``schemas/cl.schema.json`` from the CL vocabulary.

The schema documents the native format for other tools (a CAM exporter can
validate its output with any JSON Schema library).  It is generated so it can
never drift from the model; ``python -m postdsl.cl.schema`` rewrites it and a
test fails when the committed file is stale.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from postdsl.cl.model import COMMAND_TYPES, command_fields


def _field_schema(f: Any) -> dict[str, Any]:
    type_text = str(f.type)
    if "dict" in type_text:
        schema: dict[str, Any] = {
            "type": "object",
            "additionalProperties": {"type": ["number", "string"]},
        }
    elif "str" in type_text:
        schema = {"type": "string"}
        if f.metadata["choices"]:
            schema["enum"] = list(f.metadata["choices"])
    elif type_text.startswith("int"):
        schema = {"type": "integer"}
    else:
        schema = {"type": "number"}
    if "None" in type_text:
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


def main() -> None:
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else (
        Path(__file__).resolve().parents[2] / "schemas" / "cl.schema.json")
    target.write_text(render_schema(), encoding="utf-8")
    print(f"wrote {target}")


if __name__ == "__main__":
    main()
