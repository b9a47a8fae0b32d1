"""Floating-point overflow on the command line is one line and status 2, never a warning and inf.

numpy only warns (on stderr) when a result overflows or is undefined, and then
carries on with inf or NaN, which the output would print as if it were a
result. Inside `strict_arithmetic` those operations raise instead, and the
error becomes a UserError. Code that expects such values (e.g. a relative
error of a zero estimate) sets its own np.errstate and checks the result.
The explorer is not run inside it: there a warning is harmless, an exception not.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from .arguments import UserError


@contextmanager
def strict_arithmetic() -> Iterator[None]:
    """Run the block with numpy's overflow, invalid-operation and division warnings raised as one-line UserErrors."""
    import numpy as np  # here, not at the top: the parser and --help must not load numpy

    with np.errstate(over="raise", invalid="raise", divide="raise"):
        try:
            yield
        except (FloatingPointError, OverflowError) as error:
            raise UserError(
                f"a result is not a finite number in double precision ({error}); use values of ordinary size"
            ) from None
