"""Keep a saved post byte-identical outside what the user edited.

ruamel.yaml's round trip keeps comments and key order, but its emitter may
still normalise a few spellings it cannot record (quoting, flow-style corner
cases, blank lines).  A post reviewed in git must not change where nobody
touched it, so saving is a three-way merge of lines:

* ``original`` — the text as it is now (on disk, or after earlier edits),
* ``before``  — ruamel's dump of that text's document, before the edit,
* ``after``   — ruamel's dump of the document after the edit.

Wherever ``before`` and ``after`` agree, the edit did not touch the text, so
the original's own spelling of that region is kept; only regions the edit
changed take ruamel's spelling.
"""

from __future__ import annotations

from difflib import SequenceMatcher


def merge_edit(original: str, before: str, after: str) -> str:
    """``after`` with every region the edit left alone spelled as in ``original``."""
    if before == original:
        return after
    crlf = "\r\n" in original
    if crlf:
        original = original.replace("\r\n", "\n")
    o_lines = original.splitlines(keepends=True)
    b_lines = before.splitlines(keepends=True)
    a_lines = after.splitlines(keepends=True)

    # B line -> A line, for the lines the edit kept; B positions where the edit inserted
    kept: dict[int, int] = {}
    inserted: set[int] = set()
    for tag, i1, i2, j1, _j2 in SequenceMatcher(None, b_lines, a_lines,
                                                autojunk=False).get_opcodes():
        if tag == "equal":
            for offset in range(i2 - i1):
                kept[i1 + offset] = j1 + offset
        elif tag == "insert":
            inserted.add(i1)

    # regions where ruamel's spelling differs from the original's
    replacements: list[tuple[int, int, list[str]]] = []
    for tag, i1, i2, j1, j2 in SequenceMatcher(None, b_lines, o_lines,
                                               autojunk=False).get_opcodes():
        if tag == "equal":
            continue
        if i2 > i1:
            # the kept lines' images (a line the edit did not keep has none)
            images = [kept[i] for i in range(i1, i2) if i in kept]
            if len(images) < i2 - i1 or \
                    images != list(range(images[0], images[0] + len(images))):
                continue  # the edit touched this region: ruamel's spelling stays
            start, end = images[0], images[0] + (i2 - i1)
        else:
            # the original has lines ruamel dropped (blank lines…): put them back after the
            # line they followed, unless the edit inserted something at that very place
            if i1 in inserted or (i1 > 0 and i1 - 1 not in kept):
                continue
            start = end = kept[i1 - 1] + 1 if i1 > 0 else 0
        replacements.append((start, end, o_lines[j1:j2]))

    for start, end, lines in sorted(replacements, reverse=True):
        a_lines[start:end] = lines
    text = "".join(a_lines)
    return text.replace("\n", "\r\n") if crlf else text
