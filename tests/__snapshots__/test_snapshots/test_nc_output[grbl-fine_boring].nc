REFUSED (no NC program is written): fine_boring.jsonl:5: fine_boring: GRBL has no canned cycles and no oriented spindle stop: fine boring cannot be written as moves without dragging the finished wall
