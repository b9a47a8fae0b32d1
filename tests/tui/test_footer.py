"""The one-line key footer: the keys that work now, fitted to the width."""

from __future__ import annotations

import asyncio

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support.tui_support import make_app

from jointid.synthetic.fourier import FourierMotion
from jointid.synthetic.settings import Settings
from tui.screens.main import VIEWS_GROUP, MainScreen
from tui.widgets.footer import KeyEntry, KeyFooter, footer_line


DESIGNED = Settings(motion=FourierMotion(8.0, 0.0, (0.0, 0.0, 1.2), (0.0, 0.0, 0.4)), noise=0.2)
"""The explorer opened on a motion file: the designed motion is the list's fourth, key 4."""


def footer_text(size, focus: str | None = None, settings: Settings | None = None) -> str:
    return footer_and_side(size, focus, settings)[0]


def footer_and_side(size, focus: str | None = None, settings: Settings | None = None) -> tuple[str, bool]:
    """The footer's text and whether the side panel shows a scrollbar."""
    async def main():
        app = make_app(settings)
        async with app.run_test(size=size) as pilot:
            await pilot.pause()
            if focus is not None:
                app.screen.query_one(focus).focus()
                await pilot.pause()
            return app.screen.query_one(KeyFooter).text, app.screen.query_one("#side").show_vertical_scrollbar

    return asyncio.run(main())


def shown_bindings(number_field_focused: bool) -> list[str]:
    """'key description' for each of the main screen's footer bindings, as Textual displays keys."""
    hidden = {"close_log"} | ({"motion('rich')", "residuals"} if number_field_focused else set())
    entries = []
    for binding in MainScreen.BINDINGS:
        if binding.action in hidden or binding.action.startswith("motion(") or not binding.show:
            continue
        key = {"question_mark": "?", "ctrl+o": "^o", "ctrl+s": "^s"}.get(binding.key, binding.key)
        entries.append(f"{key} {binding.description}")
    return entries


def test_a_wide_footer_names_every_key_and_the_palette_at_the_right_end():
    text = footer_text((120, 40))
    assert text.startswith("1 2 3 Motion r Reset")
    for entry in shown_bindings(number_field_focused=False):
        assert f" {entry}" in text  # the views' keys each with its own name
    assert text.rstrip().endswith("│ ^p")  # the palette's word gave way to the keys' names (help lists it)
    assert len(text) == 120 - 2  # the footer's padding


def test_80_columns_show_every_key_of_the_main_screen_but_quit():
    text = footer_text((80, 24))
    views = {binding.key for binding in MainScreen.BINDINGS if binding.group is VIEWS_GROUP}
    for entry in shown_bindings(number_field_focused=False):
        key = entry.split(" ", 1)[0]
        assert key in views or key == "q" or entry in text
    assert "1 2 3 Motion" in text and "s m e l d Views" in text and "…" not in text and "Quit" not in text


def test_a_number_field_hides_the_keys_it_takes_as_typing():
    text = footer_text((120, 40), focus="#noise")
    assert "Motion" not in text  # digits type; e cannot start a number, so it stays the residuals' key
    assert "r Reset" in text and "s Sweep" in text and "e Residuals" in text


def test_80_columns_keep_export_and_no_scrollbar_with_a_designed_motion():
    text, scrollbar = footer_and_side((80, 24), settings=DESIGNED)
    assert text.rstrip() == "1 2 3 4 Motion r Reset ? Help s m e l d Views p Physics ^o Open log ^s Export"
    assert not scrollbar  # Reset gives way to the motion list's fourth row (r still works)


@pytest.mark.parametrize("size", [(80, 24), (100, 30), (120, 40), (160, 40)])
@pytest.mark.parametrize("settings", [None, DESIGNED], ids=["lesson", "designed"])
def test_a_key_and_its_description_are_one_space_apart_at_every_width(size, settings):
    """The footer flipped between `rReset ?Help` and `r Reset ? Help` (and `^ppalette`) with the width and the motions."""
    text = footer_text(size, settings=settings)
    assert "r Reset" in text and "? Help" in text and "^o Open log" in text and "^s Export" in text
    assert "rReset" not in text and "?Help" not in text and "^ppalette" not in text and "^oOpen" not in text


def test_at_120_columns_a_designed_motion_keeps_every_key_named_and_the_palette_key_gives_way():
    text = footer_text((120, 40), settings=DESIGNED)
    assert "1 2 3 4 Motion r Reset ? Help q Quit s Sweep m Matrix" in text and text.rstrip().endswith("^s Export")
    assert "^p" not in text and "│" not in text


@pytest.mark.parametrize("settings", [None, DESIGNED], ids=["lesson", "designed"])
@pytest.mark.parametrize("focus", [None, "#motion", "#noise", "#seed", "#reset"])
def test_at_80_columns_focus_changes_the_keys_shown_but_not_the_spacing_or_the_palette(focus, settings):
    text = footer_text((80, 24), focus, settings)
    assert "r Reset ? Help s m e l d Views p Physics ^o Open log ^s Export" in text
    assert "^p" not in text and "│" not in text  # the palette's key is dropped at 80 columns, as documented
    # A number field takes digits as typing, so the motion keys leave; nothing else moves.
    assert text.startswith("r Reset" if focus in ("#noise", "#seed") else "1 2 3")


def test_a_number_field_keeps_the_wide_spacing_at_120_columns():
    assert footer_text((120, 40), "#noise").split("│")[0].rstrip() == footer_text((120, 40)).split(
        "│")[0].rstrip().removeprefix("1 2 3 Motion ")


def test_below_80_columns_the_keys_that_fit_and_an_ellipsis():
    text = footer_text((70, 22))
    assert text.rstrip().endswith("…") and len(text) == 70 - 2
    assert text.startswith("1 2 3 Motion")


keys = st.text(alphabet="abcxyz^123 ", min_size=1, max_size=5).map(str.strip).filter(bool)
entries = st.lists(st.builds(KeyEntry, keys, st.text(alphabet="abcdef ", max_size=12), st.booleans()), max_size=14)


@given(entries=entries, palette=st.none() | st.builds(KeyEntry, keys, st.just("palette")),
       width=st.integers(10, 200))
def test_the_line_always_fills_the_width_exactly(entries, palette, width):
    line = footer_line(tuple(entries), palette, width)
    assert line.cell_length == width


@pytest.mark.parametrize("width", [30, 60, 118])
def test_the_roomiest_arrangement_that_fits_is_chosen(width):
    entries = tuple(KeyEntry(key, description) for key, description in
                    [("a", "Alpha"), ("b", "Beta"), ("c", "Gamma"), ("d", "Delta")])
    text = footer_line(entries, KeyEntry("^p", "palette"), width).plain
    if width >= 118:
        assert text.startswith("a Alpha  b Beta  c Gamma  d Delta ") and text.endswith("│ ^p palette")
    elif width == 60:
        assert text.startswith("a Alpha  b Beta")
    else:
        assert text.startswith("a Alpha b Beta c Gamma d Delta")
