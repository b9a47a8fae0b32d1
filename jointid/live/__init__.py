"""Live sources: samples that arrive while the joint moves (NetworkTables 4, a CSV being appended), read in
blocks and handed to the same estimation as a recorded log (studies/watch.py refits them incrementally).

    opening.open_live_source(nt=... | csv=..., ...)  -> a LiveSource (received.LiveSource)
    network_tables.NetworkTablesSource, growing_csv.GrowingCsv   the two sources
    received.Received                                 what each poll(timeout) returns
    received_log.ReceivedLog                          everything received, written as a CSV log at the end
"""
