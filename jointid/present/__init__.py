"""The presentation layer: every text, table, chart series and JSON document jointid shows.

Pure functions of the core's result objects, with no Textual or plotext: the
command line prints them and the explorer displays them, so each text is
written once and the two faces cannot disagree.

- `text`: number formatting, word lists, aligned tables, the settings header;
- `status`: the status sentence and the warnings under a fit;
- `readouts`: the lab's readouts, precision notes and the uncertainty text;
- `tables`: the sweep statistics and the cross-excitation matrix;
- `charts`: the series and one-line summaries of every chart;
- `documents`: the JSON documents of `jointid ... --json` and the explorer's export;
- `notes`, `summary`, `runs`: a log fit's notes and what it left out, the text `jointid fit` prints (the
  library's `summary()`), and several runs side by side;
- `simulators`: the MJCF and URDF files `jointid export` writes, and what it prints about them.
- `report`, `report_writers`, `report_charts`, `chart_process`: `jointid report`'s page, arranged from the texts
  above, written as HTML or Markdown, its charts drawn by matplotlib (the `jointid[report]` extra), in a second
  process when the command runs.
"""
