"""Source 1, the synthetic joint: settings in, samples out.

- `settings`: one frozen object of every experiment setting, checked on creation;
- `motions`: the lesson's prescribed motions with analytic derivatives;
- `fourier`: designed finite-Fourier-series motions and their motion files;
- `noise`: the lesson's repeatable bounded torque noise;
- `samples`: the training and held-out samples of an experiment.
"""
