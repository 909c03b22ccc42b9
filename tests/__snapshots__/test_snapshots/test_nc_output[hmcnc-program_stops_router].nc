REFUSED (no NC program is written): program_stops_router.jsonl:9: optional_stop: hmCNC has no optional stop: its commands (thesis 7.1) run the program to its end; post the program in parts
