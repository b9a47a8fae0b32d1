"""What is identified: the joint model as data, and the synthetic joint's truth.

- `terms`: the terms and models (plain, coulomb, bias, angle-offset), the regressor and inverse dynamics;
- `breakdown`: the plain model's torque split into its contributions (`jointid torque`);
- `truth`: the synthetic joint the experiments measure, with optional missing physics;
- `rigid_link`: the rigid link behind an identified I and h, given its mass (`jointid export`).
"""
