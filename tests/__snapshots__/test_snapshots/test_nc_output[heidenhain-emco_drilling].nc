REFUSED (no NC program is written): emco_drilling.jsonl:74: rigid_tapping_ccw: cycles 207 and 209 (rigid tapping) have no dwell at the bottom
