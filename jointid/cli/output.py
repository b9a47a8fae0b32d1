"""What the subcommands print as JSON: strict JSON only, never Infinity or NaN."""

from __future__ import annotations

from .arguments import UserError


def print_json(document) -> None:
    """Print a document as strict JSON; UserError (one line) if any value in it is not finite."""
    from ..present.documents import NonFiniteValue, json_text  # numpy-backed: only when printing

    try:
        text = json_text(document)
    except NonFiniteValue as error:
        # A value the documents did not already turn into null: refuse rather than print a
        # non-standard token that strict parsers reject.
        raise UserError(
            f"the result's {error.key} is not a finite number (it overflows double precision); "
            "no JSON printed: use smaller values"
        ) from None
    print(text)
