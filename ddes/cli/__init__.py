"""The ``ddes`` command line: demo, ROS tool subcommands, console."""
