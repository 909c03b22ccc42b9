REFUSED (no NC program is written): vmc500_cycles.jsonl:36: rigid_tapping: cycles 207 and 209 (rigid tapping) have no dwell at the bottom
