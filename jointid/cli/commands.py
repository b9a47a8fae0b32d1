"""Every subcommand: the module that defines it and the one line `jointid --help` gives it.

The lines live here rather than in the modules so that a command line builds
the full parser of the one subcommand it names and imports no other
subcommand's module (every parser built cost 13 ms of each start, the
explorer's included; benchmarks/README.md, 2026-11-26).
"""

from __future__ import annotations


class Subcommand:
    """A subcommand's module and help line (a plain class: dataclasses' import alone costs a --help 7 ms)."""

    __slots__ = ("module", "summary", "lasting")

    def __init__(self, module: str, summary: str, lasting: bool = False) -> None:
        self.module = module
        """The module in jointid.cli that defines it: its NAME, add_parser(subparsers) and run(args)."""
        self.summary = summary
        """Its line in `jointid --help`."""
        self.lasting = lasting
        """Whether it runs until stopped (its process then collects reference cycles: console_script)."""


SUBCOMMANDS = {
    "fit": Subcommand("fit_command", "fit a joint model (I, h, B and any --model terms) to one experiment or log"),
    "compare": Subcommand("compare_command",
                          "fit every model of the ladder on the same data and say which one BIC prefers"),
    "torque": Subcommand("torque_command", "actuator torque at one state, with each contribution"),
    "sweep": Subcommand("sweep_command", "repeat one experiment over many noise seeds and summarise the estimates"),
    "matrix": Subcommand("matrix_command",
                         "fit each training motion and predict every motion: a table of torque RMSE"),
    "simulate": Subcommand("simulate_command", "write a synthetic joint log (CSV) to try fit --csv on"),
    "design": Subcommand("design_command",
                         "design the periodic motion that determines the parameters best within the joint's limits"),
    "export": Subcommand("export_command", "write the identified joint as a MuJoCo model (MJCF) and/or a URDF robot"),
    "report": Subcommand("report_command",
                         "write the fit as one self-contained HTML report (and optionally Markdown) to hand in"),
    "bag-info": Subcommand("bag_info_command",
                           "list a ROS bag's topics and the joints of its JointState topics (for --bag/--joint)"),
    "log-info": Subcommand("log_info_command",
                           "list a WPILib data log's entries and any SysId routine in it (for --wpilog/--entry)"),
    "watch": Subcommand("watch_command",
                        "fit a joint while it moves (a growing CSV or NetworkTables 4) and say when each parameter "
                        "is determined", lasting=True),
    "serve": Subcommand("serve_command", "serve the explorer to web browsers, one session per tab (needs pip install "
                        "'jointid[web]')", lasting=True),
}
"""Each subcommand by name, in help order."""
