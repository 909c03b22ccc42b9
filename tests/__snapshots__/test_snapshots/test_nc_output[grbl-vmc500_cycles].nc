REFUSED (no NC program is written): vmc500_cycles.jsonl:32: tapping: GRBL has no tapping cycle and no spindle synchronised with Z: a tap cannot be cut
