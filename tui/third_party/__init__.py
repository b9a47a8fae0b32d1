"""Everything that touches plotext's, textual-plotext's or Textual's internals: `adapter` checks the pinned
versions and switches each adaptation on at start-up; `plotext_speedups` holds the plotext replacements."""
