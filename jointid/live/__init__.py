"""Live sources: samples that arrive while the joint moves (NetworkTables 4, a CSV being appended), read in
blocks and handed to the same estimation as a recorded log (studies/watch.py refits them incrementally)."""
