REFUSED (no NC program is written): emco_drilling.jsonl:50: tapping: GRBL has no tapping cycle and no spindle synchronised with Z: a tap cannot be cut
