"""Samples to a fit: the regressor's least squares, and how well it determines each parameter.

- `solver`: column-scaled, column-pivoted Householder least squares with a rank check;
- `low_pass`: one zero-phase low-pass applied alike to the torque and every regressor column, its cutoff from
  the motion;
- `exclusion`: what a log's fit leaves out: outside torques (a robust fit) and standstill;
- `fit`: a model fitted to joint data, and its result;
- `uncertainty`, `student_t`: standard errors, intervals and verdicts;
- `bounded`, `identifiable`, `residuals`: the sign-constrained fit, what a rank-deficient fit still
  determines, and the residuals against time and state.
"""
