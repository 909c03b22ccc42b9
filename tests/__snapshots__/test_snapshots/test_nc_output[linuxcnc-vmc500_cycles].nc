REFUSED (no NC program is written): vmc500_cycles.jsonl:36: rigid_tapping: LinuxCNC's G33.1 taps in one stroke: a pecked rigid tap cannot be written
