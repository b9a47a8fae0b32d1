"""The lesson's guided tour as command palette entries."""

from __future__ import annotations

from dataclasses import replace

from textual.command import DiscoveryHit, Hit, Hits, Provider

from jointid.motions import TRAINING_MOTIONS
from jointid.settings import DEFAULT_SETTINGS, Settings

TOUR = (
    replace(DEFAULT_SETTINGS, motion="rich", noise=0.0),
    replace(DEFAULT_SETTINGS, motion="rich", noise=0.2),
    replace(DEFAULT_SETTINGS, motion="slow", noise=0.2),
    replace(DEFAULT_SETTINGS, motion="holds", noise=0.0),
)
"""The lesson's four stops: rich 0.00, rich 0.20, slow 0.20, holds; 24 samples, seed 7."""

TOUR_NOTES = (
    "exact data recovers I = 0.8, h = 0.4, B = 0.15",
    "noise moves the fit a little; held-out error stays small",
    "small training error, negative inertia, large held-out error",
    "rank 1: no unique fit, readouts unavailable",
)
"""What each tour stop shows, as palette help text."""


def tour_title(index: int, settings: Settings) -> str:
    """Palette text for one tour stop, e.g. 'Tour 2: Rich motion, noise 0.20'."""
    label = TRAINING_MOTIONS[settings.motion].label
    return f"Tour {index + 1}: {label}, noise {settings.noise:.2f}"


class TourCommands(Provider):
    """Command palette entries that set all four controls to one of the lesson's tour stops."""

    def _entries(self):
        screen = self.screen
        for index, settings in enumerate(TOUR):
            callback = getattr(screen, "apply_settings", None)
            if callback is None:  # palette opened over a screen without controls (help)
                return
            yield tour_title(index, settings), TOUR_NOTES[index], (lambda s=settings: callback(s))

    async def discover(self) -> Hits:
        """List the tour stops when the palette opens with no query."""
        for title, note, callback in self._entries():
            yield DiscoveryHit(title, callback, help=note)

    async def search(self, query: str) -> Hits:
        """Tour stops whose title matches the query."""
        matcher = self.matcher(query)
        for title, note, callback in self._entries():
            score = max(matcher.match(title), matcher.match(f"{title} {note}"))
            if score > 0:
                yield Hit(score, matcher.highlight(title), callback, help=note)
