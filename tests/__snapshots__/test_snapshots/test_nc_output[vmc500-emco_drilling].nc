REFUSED (no NC program is written): emco_drilling.jsonl:50: tapping: the Acramatic cycle leaves the tool at R + GAGE_HT_MM (top + clearance): a higher retract plane cannot be written
