"""The explorer's screens: the main screen, the analysis views, help and the dialogs."""
