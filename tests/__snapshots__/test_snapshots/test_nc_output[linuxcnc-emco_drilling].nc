REFUSED (no NC program is written): emco_drilling.jsonl:32: break_chip: LinuxCNC's G83 and G73 have no dwell at the bottom (P is G82's): a pecked hole with a dwell cannot be written
