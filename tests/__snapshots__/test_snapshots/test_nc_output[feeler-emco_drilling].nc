REFUSED (no NC program is written): emco_drilling.jsonl:32: break_chip: the Fanuc 0i's G73 has no dwell at the bottom (no P word)
