REFUSED (no NC program is written): fine_boring_router.jsonl:5: fine_boring: the hmCNC router has no oriented spindle stop: fine boring cannot be written as moves without dragging the finished wall
