"""Reading the NC back: each control's model replays the posted program into motion
events, and verify compares them with the CL the program was posted from."""
