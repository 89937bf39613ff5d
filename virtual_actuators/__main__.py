"""Command line: ``python -m virtual_actuators demo`` and friends."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from .cli.commands import check_results_path, run
from .cli.options import attach_values, build_parser
from .cli.usage_errors import (
    OptionError,
    check_demo_options,
    check_installed,
    tolerate_closed_pipes,
)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``python -m virtual_actuators``.

    A bad option, or a [`VirtualActuatorError`][] its values cause, is a usage error (exit code 2);
    any other exception is a bug and propagates. A reader that closes the output early ends nothing.

    Args:
        argv: The arguments (default: ``sys.argv[1:]``); none, or options first, means ``demo``.

    Returns:
        The exit code: 0, or 1 when a walk ends with the robot fallen.

    Raises:
        SystemExit: With code 2 (and argparse's usage message on stderr) for a bad argument, or
            with code 0 for ``--help``.
    """
    with tolerate_closed_pipes():
        return _main(list(sys.argv[1:] if argv is None else argv))


def _main(arguments: list[str]) -> int:
    parser, subparsers = build_parser()
    if not arguments or (
        arguments[0].startswith("-") and arguments[0] not in ("-h", "--help", "--version")
    ):
        arguments.insert(0, "demo")  # the default command, with its options
    args = parser.parse_args(attach_values(arguments, [parser, *subparsers.values()]))
    command_parser = subparsers.get(args.command, parser)
    if args.command == "demo":
        check_demo_options(args, command_parser)
    elif args.command == "sweep":
        check_results_path(args, command_parser)
    check_installed(args, command_parser)  # the options agree; are their packages there?
    from .exceptions import VirtualActuatorError

    try:
        return run(args)
    except (OptionError, VirtualActuatorError) as error:  # caused by the arguments: exit 2
        command_parser.error(str(error))
    return 2  # (error() exits)


if __name__ == "__main__":
    sys.exit(main())
