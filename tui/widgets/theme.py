"""Theme colours for plotext, which needs concrete RGB values rather than theme variables."""

from __future__ import annotations

from textual.color import Color


def theme_rgb(app, variable: str, faded: float = 0.0) -> tuple[int, int, int]:
    """The RGB of a theme variable (e.g. 'primary'), so charts follow the theme; `faded` (0 to 1) blends it
    that far into the background, for what is drawn but not used (samples a fit left out)."""
    variables = app.theme_variables
    colour = Color.parse(variables[variable])
    if faded:
        colour = colour.blend(Color.parse(variables["background"]), faded)
    return colour.rgb
