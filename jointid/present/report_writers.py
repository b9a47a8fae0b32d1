"""A report (`jointid.present.report`) as one self-contained HTML page, or as Markdown with its charts beside it.

The HTML page needs nothing from the network: its style is inline, its charts
are inline SVG, it names no font, script or image elsewhere. Every text is
HTML-escaped (a log's path or a note may hold `<`, `&` or quotes). The page
follows the reader's light or dark browser theme (`prefers-color-scheme`), and
the charts draw their text and axes in the page's text colour.

Markdown cannot hold SVG inline, and the data: URIs a browser would accept are
dropped by most Markdown renderers (GitHub's among them), so each chart is a
file of its own beside the Markdown (`REPORT-training.svg`, ...), linked by
name; each such file carries its own light and dark colours.
"""

from __future__ import annotations

import html
import os
import re
import urllib.parse

from .report import Chart, Heading, Paragraph, Preformatted, Report, Table

STYLE = """
:root { color-scheme: light dark; --text: #1b1b1b; --muted: #555; --rule: #ccc; --shade: #f3f3f3; }
@media (prefers-color-scheme: dark) {
  :root { --text: #e6e6e6; --muted: #a8a8a8; --rule: #444; --shade: #1e1e1e; }
  body { background: #121212; }
}
body { color: var(--text); font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif;
       margin: 0 auto; max-width: 62rem; padding: 1.5rem; }
h1, h2, h3 { line-height: 1.25; }
h2 { border-bottom: 1px solid var(--rule); padding-bottom: 0.2rem; margin-top: 2rem; }
.subject { color: var(--muted); margin-top: -0.5rem; }
pre { background: var(--shade); padding: 0.6rem 0.8rem; overflow-x: auto; font-size: 13px; white-space: pre-wrap; }
table { border-collapse: collapse; margin: 0.8rem 0; font-variant-numeric: tabular-nums; }
th, td { border-bottom: 1px solid var(--rule); padding: 0.25rem 0.7rem; vertical-align: top; }
th { text-align: left; }
td { text-align: right; }
td.words { text-align: left; }
caption { caption-side: bottom; text-align: left; color: var(--muted); font-size: 13px; padding-top: 0.3rem; }
figure { margin: 1rem 0 1.5rem; break-inside: avoid; }
figure svg { width: 100%; height: auto; color: var(--text); }
figcaption { color: var(--muted); font-size: 13px; }
footer { color: var(--muted); font-size: 13px; margin-top: 2.5rem; border-top: 1px solid var(--rule); }
@media print {
  :root { color-scheme: light; --text: #000; --muted: #444; --rule: #bbb; --shade: #f3f3f3; }
  body { background: none; max-width: none; padding: 0; font-size: 11pt; }
  h2, h3 { break-after: avoid; }
}
""".strip()
"""The page's whole style sheet: system fonts only, colours for light and dark themes, and print (always dark on
light: paper, even from a browser in a dark theme)."""

SVG_FILE_STYLE = ("<style>svg { color: #1b1b1b; } @media (prefers-color-scheme: dark) { svg { color: #e6e6e6; } }"
                  "</style>")
"""A chart file's own text colour, light and dark (inline in the page, the page sets it instead)."""


def made_by(how: str) -> str:
    """The report's footer: 'Written by jointid 0.1.0 from: jointid report --motion slow ...'."""
    from importlib import metadata

    try:
        version = metadata.version("jointid")
    except metadata.PackageNotFoundError:
        version = "(version unknown)"
    return f"Written by jointid {version} from {how}"


def _escape(text: str) -> str:
    return html.escape(text, quote=True)


def html_page(report: Report, footer: str) -> str:
    """The whole report as one HTML5 page (UTF-8), charts inline."""
    parts = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             '<meta name="color-scheme" content="light dark">',
             f"<title>{_escape(report.title)}: {_escape(report.subject)}</title>",
             f"<style>\n{STYLE}\n</style>", "</head>", "<body>", "<main>",
             f"<h1>{_escape(report.title)}</h1>", f'<p class="subject">{_escape(report.subject)}</p>']
    parts += [_html_block(block) for block in report.blocks]
    parts += ["</main>", f"<footer><p>{_escape(footer)}</p></footer>", "</body>", "</html>"]
    return "\n".join(parts) + "\n"


def _html_block(block) -> str:
    if isinstance(block, Heading):
        anchor = f' id="{_escape(block.anchor)}"' if block.anchor else ""
        return f"<h{block.level}{anchor}>{_escape(block.text)}</h{block.level}>"
    if isinstance(block, Paragraph):
        return "\n".join(f"<p>{_escape(line)}</p>" for line in block.text.split("\n"))
    if isinstance(block, Preformatted):
        return f"<pre>{_escape(block.text)}</pre>"
    if isinstance(block, Table):
        head = "".join(f'<th scope="col">{_escape(cell)}</th>' for cell in block.header)
        rows = "\n".join("<tr>" + "".join((f'<th scope="row">{_escape(cell)}</th>' if index == 0 else
                                           _html_cell(cell)) for index, cell in enumerate(row)) + "</tr>"
                         for row in block.rows)
        caption = f"<caption>{_escape(block.caption)}</caption>" if block.caption else ""
        return f"<table>{caption}\n<thead><tr>{head}</tr></thead>\n<tbody>\n{rows}\n</tbody></table>"
    if isinstance(block, Chart):
        return (f'<figure id="chart-{_escape(block.name)}" role="group" aria-label="{_escape(block.title)}">\n'
                f"{_titled_svg(block)}<figcaption>{_escape(block.caption)}</figcaption></figure>")
    raise TypeError(f"not a report block: {block!r}")


_NUMBER_CELL = re.compile(r"^(?:[-+±\[(]|\d|$)")
"""A cell that holds a number, an interval or nothing: right-aligned so decimals line up; words are left-aligned."""


def _html_cell(cell: str) -> str:
    words = "" if _NUMBER_CELL.match(cell) else ' class="words"'
    return f"<td{words}>{_escape(cell)}</td>"


def _titled_svg(chart: Chart) -> str:
    """The chart's SVG with a role and its title for screen readers (the SVG's text is matplotlib's own)."""
    return chart.svg.replace("<svg ", f'<svg role="img" aria-label="{_escape(chart.title)}" ', 1)


# Markdown ---------------------------------------------------------------------------------------------------

_MARKDOWN_SPECIAL = re.compile(r"([\\`*_{}\[\]<>|#])")


def _markdown_text(text: str) -> str:
    """Text with Markdown's markup characters escaped, so a path or a note reads as written."""
    return _MARKDOWN_SPECIAL.sub(r"\\\1", text)


def _fence(text: str) -> str:
    """A code fence longer than any run of backticks in `text`, so nothing inside can close it."""
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    return "`" * max(3, longest + 1)


def _link_target(name: str) -> str:
    """A file name as a link's destination: percent-encoded, so spaces and parentheses do not end the link."""
    return urllib.parse.quote(name)


def chart_file_name(markdown_path: str, chart: Chart) -> str:
    """'slow-training.svg' beside 'slow.md'."""
    stem = os.path.splitext(os.path.basename(markdown_path))[0]
    return f"{stem}-{chart.name}.svg"


def markdown_files(report: Report, markdown_path: str, footer: str) -> dict[str, str]:
    """{path: text} of the Markdown report and its chart files, in the Markdown's folder."""
    folder = os.path.dirname(markdown_path)
    lines = [f"# {_markdown_text(report.title)}", "", _markdown_text(report.subject), ""]
    files: dict[str, str] = {}
    for block in report.blocks:
        if isinstance(block, Heading):
            lines += [f"{'#' * (block.level + (1 if block.level == 1 else 0))} {_markdown_text(block.text)}", ""]
        elif isinstance(block, Paragraph):
            lines += [_markdown_text(block.text), ""]
        elif isinstance(block, Preformatted):
            fence = _fence(block.text)
            lines += [fence + "text", block.text, fence, ""]
        elif isinstance(block, Table):
            numbers = [all(_NUMBER_CELL.match(row[index]) for row in block.rows)
                       for index in range(1, len(block.header))]
            lines += ["| " + " | ".join(map(_markdown_text, block.header)) + " |",
                      "|" + "|".join([":---", *("---:" if number else ":---" for number in numbers)]) + "|",
                      *("| " + " | ".join(map(_markdown_text, row)) + " |" for row in block.rows), ""]
            if block.caption:
                lines += [_markdown_text(block.caption), ""]
        elif isinstance(block, Chart):
            name = chart_file_name(markdown_path, block)
            files[os.path.join(folder, name)] = svg_file(block.svg)
            lines += [f"![{_markdown_text(block.title)}]({_link_target(name)})", "", _markdown_text(block.caption), ""]
    lines += ["---", "", _markdown_text(footer), ""]
    return {markdown_path: "\n".join(lines), **files}


def svg_file(svg: str) -> str:
    """A chart as a standalone SVG file: XML declaration, and its own light and dark text colour."""
    body = re.sub(r"(<svg [^>]*>)", lambda match: match.group(1) + SVG_FILE_STYLE, svg, count=1)
    return '<?xml version="1.0" encoding="utf-8" standalone="no"?>\n' + body
