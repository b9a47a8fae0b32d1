"""Theme colours for plotext, which needs concrete RGB values rather than theme variables."""

from __future__ import annotations

from textual.color import Color


def theme_rgb(app, variable: str) -> tuple[int, int, int]:
    """The RGB of a theme variable (e.g. 'primary'), so charts follow the theme."""
    return Color.parse(app.theme_variables[variable]).rgb
