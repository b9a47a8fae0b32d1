"""The product's questions, each a function returning a frozen result built on fits.

experiment (one synthetic fit), sweep (many noise seeds), cross_excitation (fit each motion, predict every
motion), ladder (the models compared by BIC), simulation (integrate the fitted model), log_fit (fit a
recorded log) with its sensitivity check, runs (several runs of one joint, alone and together), and design (the motion that reveals the parameters best) with
design_process (the designer in a child process), and mujoco_check (an exported model read back by MuJoCo).
"""
