REFUSED (no NC program is written): emco_drilling.jsonl:32: break_chip: Fanuc's G73 has no dwell at the bottom (no P word)
