"""The lesson's guided tour as command palette entries."""

from __future__ import annotations

from dataclasses import replace

from textual.command import DiscoveryHit, Hit, Hits, Provider

from jointid.synthetic.settings import DEFAULT_SETTINGS, Settings

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


PHYSICS_STOPS = (
    ("Coulomb friction, plain model", replace(DEFAULT_SETTINGS, noise=0.05, true_coulomb=0.3),
     "the plain model absorbs friction in its damping (about 0.45) and mispredicts; e, 3: a step at qd = 0"),
    ("Coulomb friction, Coulomb model", replace(DEFAULT_SETTINGS, noise=0.05, true_coulomb=0.3, model="coulomb"),
     "the Fc*sign(qd) term finds the friction and the held-out error drops"),
    ("Sensor bias", replace(DEFAULT_SETTINGS, noise=0.05, true_bias=0.2, model="bias"),
     "a bias term finds it, but trades with gravity: condition number about 17"),
    ("Angle offset", replace(DEFAULT_SETTINGS, noise=0.05, true_angle_offset=0.1, model="angle-offset"),
     "a g*sin(q) column recovers the encoder offset q0 = 0.1 rad and h"),
)
"""Stops beyond the lesson, where real joints are: (palette title, settings, what it shows)."""


def tour_title(index: int, settings: Settings) -> str:
    """Palette text for one tour stop, e.g. 'Tour 2: Rich motion, noise 0.20'."""
    label = settings.training_motion.label
    return f"Tour {index + 1}: {label}, noise {settings.noise:.2f}"


class TourCommands(Provider):
    """Command palette entries that set every control to one of the tour's stops (the lesson's four, then
    missing physics)."""

    def _entries(self):
        callback = getattr(self.screen, "apply_settings", None)
        if callback is None:  # palette opened over a screen without controls (help)
            return
        stops = [(tour_title(index, settings), note, settings) for index, (settings, note)
                 in enumerate(zip(TOUR, TOUR_NOTES))]
        stops += [(f"Tour {len(TOUR) + index + 1}: {title}", note, settings)
                  for index, (title, settings, note) in enumerate(PHYSICS_STOPS)]
        for title, note, settings in stops:
            yield title, note, (lambda s=settings: callback(s))

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
