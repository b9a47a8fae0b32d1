"""Which parameters the data determine on their own, at any rank.

Every least-squares solution is one of them plus a vector of the regressor's
null space, so parameter j takes the same value in all of them exactly when the
unit vector e_j is orthogonal to that null space. The null space comes from the
pivoted factorisation X D^-1 P = Q [R11 R12]: its basis is P [-R11^-1 R12; I]
(in the scaled coordinates, which have the same zero pattern as the original
ones). The determined values are read from the basic solution.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .solver import LeastSquaresSolution, back_substitute

IDENTIFIABLE_TOLERANCE = 1e-8
"""A parameter is determined alone when e_j's projection onto the (orthonormal) null space is at most this."""


def null_space(solution: LeastSquaresSolution) -> np.ndarray:
    """(p, p - rank) Orthonormal basis of the column-scaled regressor's null space, original order."""
    rank, p = solution.rank, solution.column_count
    pivoted = np.zeros((p, p - rank))
    pivoted[rank:] = np.eye(p - rank)
    if rank:
        pivoted[:rank] = -back_substitute(solution.r_factor[:, :rank], solution.r_factor[:, rank:])
    basis = np.empty_like(pivoted)
    basis[solution.permutation] = pivoted
    return np.linalg.qr(basis)[0] if p - rank else basis


@dataclass(frozen=True, eq=False)
class IdentifiableSubset:
    """The parameters the data determine alone, with their values."""

    names: tuple[str, ...]
    """Every parameter's name, in theta order."""
    null_basis: np.ndarray
    """(p, p - rank) Orthonormal basis of the scaled regressor's null space."""
    basic_estimate: np.ndarray
    """(p,) A least-squares solution; its determined entries are the same in every one."""
    zero_columns: np.ndarray
    """(p,) True where the regressor column is entirely zero (the data never excite it)."""

    @cached_property
    def null_projection(self) -> np.ndarray:
        """(p,) Length of each unit vector's projection onto the null space (0: determined alone)."""
        return np.sqrt(np.einsum("ij,ij->i", self.null_basis, self.null_basis))

    @cached_property
    def determined(self) -> np.ndarray:
        """(p,) True for each parameter the data determine on its own."""
        return self.null_projection <= IDENTIFIABLE_TOLERANCE

    @cached_property
    def values(self) -> dict[str, float]:
        """Determined parameters and their values, in theta order."""
        return {
            name: float(value)
            for name, value, ok in zip(self.names, self.basic_estimate, self.determined)
            if ok
        }

    @property
    def undetermined(self) -> tuple[str, ...]:
        """Names of the parameters the data leave free."""
        return tuple(name for name, ok in zip(self.names, self.determined) if not ok)


def identifiable_subset(solution: LeastSquaresSolution, names: tuple[str, ...]) -> IdentifiableSubset:
    """Find which of the named parameters a single-RHS solution determines alone."""
    # A column's coordinates in the pivoted R are all zero only when the column is:
    # orthogonal transformations preserve its norm (up to the rank tolerance).
    coordinates = np.zeros(solution.column_count)
    coordinates[solution.permutation] = np.sqrt(np.einsum("ij,ij->j", solution.r_factor, solution.r_factor))
    return IdentifiableSubset(
        names=tuple(names),
        null_basis=null_space(solution),
        basic_estimate=solution.basic_estimate,
        zero_columns=coordinates <= IDENTIFIABLE_TOLERANCE,
    )
