"""What every ``focas-net`` command shares: exit codes, the one-line error, argument types,
the parser class.

An argument type is a parser of the command-line form (``ValueError`` with a message naming
what the user typed) wrapped by :func:`argument_type` for ``argparse``. Every parser is a
:class:`Parser`, whose usage error is one line, ``focas-net CMD: error: argument --port: port
must be 1..65535, got '70000'; see focas-net CMD --help``, and exit 2.
"""

from __future__ import annotations

import argparse
import math
import re
import shlex
import sys
from collections.abc import Callable, Sequence
from functools import partial
from typing import Any, Final, NoReturn, TypeVar

from focas_net._address import (
    check_host,
    host_and_port,
    shown,
    split_advice,
    url_address,
    url_advice,
)
from focas_net._tls import pem_holds, ssl_error_text
from focas_net._typed import (
    alarm_axis_unfit,
    file_name_unfit,
    item_axis_unfit,
    lead_as_typed,
    override_unfit,
    rapid_step,
    read_otherwise,
    typed_number,
    typed_numbers,
)
from focas_net.client._values import check_path, history_depth
from focas_net.protocol import Password, PmcArea

from . import _format as fmt

__all__ = [
    "ALARM_AXIS",
    "AREA",
    "BOOL",
    "DIAG_AXIS",
    "EXIT_CNC",
    "EXIT_CODES",
    "EXIT_CONNECTION",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_PROTOCOL",
    "EXIT_USAGE",
    "FEED",
    "FILE_NAME",
    "HISTORY_DEPTH",
    "HOST",
    "INT",
    "INTERVAL",
    "LISTEN_HOST",
    "LISTEN_PORT",
    "LOG_LEVEL",
    "LOG_LEVELS",
    "MAX_INTERVAL",
    "MIN_INTERVAL",
    "NON_NEGATIVE",
    "PARAM_AXIS",
    "PASSWORD",
    "PATH",
    "PORT",
    "POSITIVE",
    "PROG",
    "RAPID",
    "SECONDS",
    "SPINDLE",
    "TYPED_NUMBERS",
    "USAGE_PROG",
    "WIDTH",
    "ArgumentRefused",
    "Parser",
    "argument_type",
    "choice",
    "command_parser",
    "named",
    "note_typed",
    "parse_area",
    "parse_at_least",
    "parse_bounded",
    "parse_file_name",
    "parse_history_depth",
    "parse_host",
    "parse_interval",
    "parse_log_level",
    "parse_non_negative",
    "parse_one_of",
    "parse_override",
    "parse_path",
    "parse_port",
    "parse_positive",
    "parse_seconds",
    "pem_holds",
    "print_error",
    "print_usage_error",
    "ssl_error_text",
    "typed_lead",
    "typed_number_bit",
    "usage_refusal",
]

T = TypeVar("T")

PROG: Final = "focas-net"

#: Success.
EXIT_OK: Final = 0
#: A client command: the CNC answered an EW code (or a chunked PMC write failed part way);
#: ``serve``: a listener could not start (port in use, ...).
EXIT_CNC: Final = 1
#: Bad arguments, a value the protocol cannot carry, or (``serve``) a bad configuration.
EXIT_USAGE: Final = 2
#: Connection refused or lost, or no answer within ``--timeout``.
EXIT_CONNECTION: Final = 3
#: The peer broke the wire protocol.
EXIT_PROTOCOL: Final = 4
#: Ctrl-C (SIGINT) before the command finished, as a shell reports a command SIGINT ended
#: (128 + 2); ``watch`` and ``alarms --follow``, which run until told, end with 0 instead.
EXIT_INTERRUPTED: Final = 130

#: The exit codes of the client commands with their short descriptions, as ``--help`` lists them.
EXIT_CODES: Final[tuple[tuple[int, str], ...]] = (
    (EXIT_OK, "success"),
    (EXIT_CNC, "CNC error (EW code)"),
    (EXIT_USAGE, "usage error"),
    (EXIT_CONNECTION, "connection error or timeout"),
    (EXIT_PROTOCOL, "protocol violation"),
    (EXIT_INTERRUPTED, "interrupted (Ctrl-C)"),
)


def print_error(message: str, prog: str = PROG) -> None:
    """``prog: message`` on stderr, flushed."""
    sys.stderr.write(f"{prog}: {message}\n")
    sys.stderr.flush()


def print_usage_error(message: str, prog: str) -> None:
    """A usage error of command ``prog`` (``focas-net sim fault``) in the parser's one line:
    ``prog: error: message; see prog --help``."""
    print_error(f"error: {message}; see {prog} --help", prog)


class ArgumentRefused(ValueError):
    """An argument's value refused by a rule the command checks rather than the parser (it
    needs another argument too, as ``sim fault --arg`` the fault's kind, or is read by the
    command, as ``param set VALUE``): reported as the parser reports an argument it
    refuses, ``argument --arg: why``."""

    def __init__(self, option: str, why: str) -> None:
        super().__init__(f"argument {option}: {why}")
        self.option = option
        self.why = why


def named(argument: str, check: Callable[..., T], *given: Any) -> T:
    """``check(*given)``, its ``ValueError`` an :class:`ArgumentRefused` of ``argument`` (as
    ``--help`` names it): a value a command judges without the CNC is refused in the parser's
    words, before anything is connected."""
    try:
        return check(*given)
    except ArgumentRefused:
        raise
    except ValueError as exc:
        raise ArgumentRefused(argument, str(exc)) from None


#: The namespace's key of the ``prog`` of the parser that read it (``focas-net param set``):
#: a refusal found after parsing is worded as that parser words its own.
USAGE_PROG: Final = "usage_prog"


def usage_refusal(exc: ValueError, args: argparse.Namespace) -> None:
    """A value the command refused without the CNC (``exc``), on one line in the parser's
    words (:func:`print_usage_error`), the numbers it names as they were typed
    (:func:`typed_lead`)."""
    if isinstance(exc, ArgumentRefused):
        message = f"argument {exc.option}: {typed_lead(exc.why, args)}"
    else:
        message = typed_lead(str(exc), args)
    print_usage_error(message, str(getattr(args, USAGE_PROG, PROG)))


#: The namespace's record of the numbers typed otherwise than they read (``0x10000`` for
#: 65536), by the value read: a refusal found after the parser read them leads with them
#: (:func:`typed_lead`).
TYPED_NUMBERS: Final = "typed_numbers"


def _typed_numbers(args: argparse.Namespace) -> dict[int, str]:
    numbers: dict[int, str] = vars(args).setdefault(TYPED_NUMBERS, {})
    return numbers


def _note_typed(numbers: dict[int, str], value: int, text: str) -> None:
    if read_otherwise(text):
        numbers[value] = text.strip()


def note_typed(args: argparse.Namespace, value: object, text: str) -> None:
    """Keep ``text``, a number a command read as ``value``, for the words of a later refusal
    (:func:`typed_lead`) where it reads otherwise (``0x80000000``, read as 2147483648)."""
    if isinstance(value, int) and not isinstance(value, bool):
        _note_typed(_typed_numbers(args), value, text)


def typed_number_bit(args: argparse.Namespace, text: str, *expected: str) -> tuple[int, int | None]:
    """``NUMBER[.BIT]`` read by :func:`~focas_net.cli._format.parse_number_bit` (``expected``:
    the form its refusal names), the number as typed kept for the words of a later refusal."""
    number, bit = fmt.parse_number_bit(text, *expected)
    _note_typed(_typed_numbers(args), number, text.strip().partition(".")[0])
    return number, bit


def typed_lead(message: str, args: argparse.Namespace) -> str:
    """``message`` (a refusal of a number the command read: the client's range words, which
    name the value) led by the numbers it names as they were typed where they read otherwise
    (``0x10000 reads as 65536: PMC start address 65536 is outside 0..65535``), as every
    front end leads it (:func:`~focas_net._typed.lead_as_typed`)."""
    return lead_as_typed(message, _typed_numbers(args))


#: An argument that starts with "-" and is a negative number, not an option.
#: A line break with the indentation around it, in an argparse message.
_LINE_BREAK: Final = re.compile(r"[ \t]*\n\s*")
_NEGATIVE_VALUE: Final = re.compile(r"^-(?:\.?\d|inf$|infinity$|nan$)", re.IGNORECASE)


#: argparse's refusal of a value given to a switch (``--json=yes``).
_SWITCH_VALUE: Final = re.compile(r"^argument (\S+): ignored explicit argument ('.*')$")


#: A number written with two minus signs (``--1``, ``--0.5``): no option of focas-net reads so.
_DOUBLE_MINUS_NUMBER: Final = re.compile(r"^--\.?\d")


class Parser(argparse.ArgumentParser):
    """The parser of ``focas-net`` and of each of its commands.

    A usage error is one line naming the command, what is wrong and where the help is (exit
    2). A command's own parser (:func:`command_parser`: it has no subcommands) takes its
    options and its positional arguments in any order (``sim alarm SV0411 --axis 2 SERVO``),
    and reports an argument it does not know itself."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.leaf = False
        self._mixing = False
        #: the numbers of the parse under way typed otherwise than they read (TYPED_NUMBERS)
        self._typed: dict[int, str] = {}
        # A value a command takes, not an option: -5 and -.5 as argparse reads them, and
        # -0x10, -0b101, -1e3, -inf too (no option of focas-net starts with a digit or these).
        self._negative_number_matcher = _NEGATIVE_VALUE

    def error(self, message: str) -> NoReturn:
        # argparse wraps long messages over lines; a value's own spaces stay as typed.
        line = _LINE_BREAK.sub(" ", message.strip())
        # argparse's words for a switch written with a value (--json=yes), in plain words
        line = _SWITCH_VALUE.sub(r"argument \1: \1 takes no value, got \2", line)
        print_usage_error(line, self.prog)
        sys.exit(EXIT_USAGE)

    def _get_values(self, action: argparse.Action, arg_strings: list[str]) -> Any:
        value = super()._get_values(action, arg_strings)
        if len(arg_strings) == 1 and isinstance(value, int) and not isinstance(value, bool):
            _note_typed(self._typed, value, arg_strings[0])  # (for typed_lead)
        return value

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: Any = None
    ) -> tuple[Any, list[str]]:
        if not self.leaf:
            self._option_before_command(sys.argv[1:] if args is None else list(args))
        if not self.leaf or self._mixing:
            return super().parse_known_args(args, namespace)
        self._double_minus_number(sys.argv[1:] if args is None else list(args))
        self._mixing = True  # (the intermixed parse calls this method for each of its passes)
        self._typed = {}
        try:
            namespace, extras = self.parse_known_intermixed_args(args, namespace)
        finally:
            self._mixing = False
        setattr(namespace, TYPED_NUMBERS, self._typed)
        if extras:
            # quoted as a shell takes them back, so an empty one ('') or one with spaces shows
            self.error(f"unrecognized arguments: {shlex.join(extras)}")
        return namespace, extras

    def _double_minus_number(self, args: list[str]) -> None:
        """A usage error naming a number written with two minus signs (``--1``), which would
        read as an unknown option and leave its argument missing."""
        for word in args:
            if word == "--":
                return
            if _DOUBLE_MINUS_NUMBER.match(word):
                self.error(
                    f"argument {word!r} is no option: a negative number is written with one "
                    f"minus ({word[1:]})"
                )

    def _option_before_command(self, args: list[str]) -> None:
        """A usage error for an option of the commands given before the command
        (``focas-net --port 9400 status``), which would read as a command name."""
        if not args or not args[0].startswith("-") or args[0] in self._option_string_actions:
            return
        sub = next((a for a in self._actions if isinstance(a, argparse._SubParsersAction)), None)
        commands = {} if sub is None else sub.choices
        command = next((word for word in args if word in commands), None)
        option = args[0].partition("=")[0]
        if command is None:  # none given: name the choices, if a command has the option
            if not any(_has_option(parser, option) for parser in commands.values()):
                return
            metavar = None if sub is None else sub.metavar
            few = len(commands) <= _FEW_COMMANDS or not metavar
            command = "|".join(commands) if few else str(metavar)
        self.error(
            f"{option} is an option of the command: give it after the command "
            f"({self.prog} {command} {option} ...)"
        )


#: Commands a usage error lists by name; more are named by their metavar (``COMMAND``).
_FEW_COMMANDS: Final = 6


def _has_option(parser: argparse.ArgumentParser, option: str) -> bool:
    """Whether ``parser`` or a command under it takes ``option``."""
    if option in parser._option_string_actions:
        return True
    return any(
        _has_option(sub, option)
        for action in parser._actions
        if isinstance(action, argparse._SubParsersAction)
        for sub in action.choices.values()
    )


def command_parser(subparsers: Any, name: str, **kwargs: Any) -> argparse.ArgumentParser:
    """The parser of command ``name``, added to ``subparsers`` (a :class:`Parser` when its
    parent is one: then a command's, see there)."""
    p: argparse.ArgumentParser = subparsers.add_parser(name, **kwargs)
    if isinstance(p, Parser):
        p.leaf = True
    return p


def argument_type(parse: Callable[[str], T], what: str) -> Callable[[str], T]:
    """``parse`` as an ``argparse`` type: its ``ValueError`` message becomes the usage error."""

    def convert(text: str) -> T:
        try:
            return parse(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    convert.__name__ = what  # argparse names the type in its messages
    return convert


def choice(choices: Sequence[str], what: str) -> Callable[[str], str]:
    """An ``argparse`` type for an argument with ``choices`` (their names in lower case): a
    name in any case, spaces around it left out, as every name the command line takes is read
    (a mode, a PMC area, an EW code, ``serve --log-level``); anything else is left as typed,
    for the parser's refusal, which names it and lists the choices."""

    def convert(text: str) -> str:
        name = text.strip().lower()
        return name if name in choices else text

    convert.__name__ = what
    return convert


# -- parsers --------------------------------------------------------------------------------


def _whole(text: str, what: str) -> int:
    """A whole number as every number is read (:func:`~focas_net.cli._format.parse_int`); its
    refusal names ``what`` and keeps the rule's reason (``'' (nothing typed)``, a digit
    beyond ASCII)."""
    try:
        return fmt.parse_int(text)
    except ValueError as exc:
        why = str(exc).removeprefix("not a whole number: ")
        raise ValueError(f"not a {what}: {why}") from None


def parse_port(text: str, *, lowest: int = 1) -> int:
    """A TCP port, ``lowest``..65535, as a decimal or ``0x`` number; ``lowest`` is 0 where port
    0 asks for an ephemeral port (``serve``), 1 where a port is connected to."""
    value = _whole(text, "port number")
    if not lowest <= value <= 65_535:
        raise ValueError(f"port must be {lowest}..65535, got {text!r}")
    return value


def parse_at_least(text: str, low: int) -> int:
    """An integer of at least ``low``; its refusal names the number as typed (``0x0``)."""
    value = fmt.parse_int(text)
    if value < low:
        rule = "must not be negative" if low == 0 else f"must be at least {low}"
        raise ValueError(f"{rule}, got {text.strip()}")
    return value


def parse_positive(text: str) -> int:
    """An integer of at least 1."""
    return parse_at_least(text, 1)


def parse_bounded(text: str, *, low: int, high: int) -> int:
    """An integer within ``low..high``; its refusal names the number as typed."""
    value = fmt.parse_int(text)
    if not low <= value <= high:
        raise ValueError(f"must be {low}..{high}, got {text.strip()}")
    return value


def parse_non_negative(text: str) -> int:
    """An integer of at least 0."""
    return parse_at_least(text, 0)


def _as_typed(why: str, text: str) -> str:
    """A refusal in the machine's words, which name the value checked, led by the number as
    typed where it reads otherwise, in another base (``0x100 reads as 256: ...``)."""
    return lead_as_typed(why, typed_numbers([text]))


def parse_item_axis(what: str, text: str) -> int:
    """The axis of a ``what`` (``parameter``, ``diagnostic``), 0 for none, refused in the
    client's words (:func:`~focas_net._typed.item_axis_unfit`), so that the parser names the
    option."""
    value = fmt.parse_int(text)
    why = item_axis_unfit(value, what)
    if why is not None:
        raise ValueError(_as_typed(why, text))
    return value


def parse_alarm_axis(text: str) -> int:
    """The axis of ``sim alarm`` (0: an alarm of no axis), refused in the words of the
    clients and the page (:func:`~focas_net._typed.alarm_axis_unfit`), so that the parser
    names the option."""
    value = fmt.parse_int(text)
    why = alarm_axis_unfit(value)
    if why is not None:
        raise ValueError(_as_typed(why, text))
    return value


def parse_override(what: str, text: str) -> int:
    """The ``what`` override (``feed``, ``rapid``, ``spindle``) as typed, a whole number of
    percent (the rapid one also ``F0``), refused in the machine's words
    (:func:`~focas_net._typed.override_unfit`) when the machine would refuse it, so the
    parser names the option."""
    value = rapid_step(text) if what == "rapid" else fmt.parse_int(text)
    why = override_unfit(what, value)
    if why is not None:
        raise ValueError(_as_typed(why, text))
    return value


def parse_file_name(text: str) -> str:
    """The name of a file or a folder as typed: not empty (an empty name reads as the
    current folder, which no option means; :func:`~focas_net._typed.file_name_unfit`)."""
    why = file_name_unfit(text)
    if why is not None:
        raise ValueError(why)
    return text


def _number(text: str) -> float:
    """A number of seconds as every front end reads number text (digits, a sign, a point, or
    a whole number in ``0x``/``0b``/``0o``; no exponent, NaN or infinity:
    :func:`focas_net._typed.typed_number`)."""
    value = float(typed_number(text))
    if math.isinf(value):
        raise ValueError(f"must be finite, got {text.strip()}")
    return value


def parse_seconds(text: str) -> float:
    """A positive, finite number of seconds."""
    value = _number(text)
    if not value > 0:
        raise ValueError(f"must be positive, got {text.strip()}")
    return value


#: Shortest poll interval of ``watch`` and ``alarms --follow``, in seconds: polling faster
#: only loads the client and the CNC.
MIN_INTERVAL: Final = 0.05
#: Longest poll interval, in seconds (an hour): a longer one is a typing mistake.
MAX_INTERVAL: Final = 3600.0


def parse_interval(text: str) -> float:
    """A poll interval: seconds, :data:`MIN_INTERVAL`..:data:`MAX_INTERVAL`."""
    value = _number(text)
    if not MIN_INTERVAL <= value <= MAX_INTERVAL:
        raise ValueError(f"must be {MIN_INTERVAL:g}..{MAX_INTERVAL:g} seconds, got {text.strip()}")
    return value


def parse_host(text: str, lowest: int = 1) -> str:
    """A host to connect to (:func:`~focas_net._address.check_host`), spaces around it
    left out (spaces alone are refused as typed, as the clients refuse them); a host with a
    port points to ``--port`` (``lowest``: 0 for a host to listen on, whose port may be 0)."""
    url = url_address(text.strip())
    if url is not None:
        raise ValueError(f"{shown(text)} is a URL: {url_advice(url, True)}")
    split = host_and_port(text.strip())
    if split:
        raise ValueError(f"{shown(text)} {split_advice(split, True, lowest)}")
    return check_host(text.strip() or text, lowest)  # (spaces alone: named as typed)


def parse_password(text: str) -> str:
    """A parameter password as ``cnc_wrunlockparam`` carries it: the codec's rule
    (:meth:`Password.from_text`), in its words, checked by the parser so nothing connects
    for a bad one."""
    Password.from_text(text)
    return text


def parse_path(text: str) -> int:
    """A path of the CNC, 1..10 (:func:`~focas_net.client._values.check_path`, where both
    clients check a ``path=``)."""
    value = _whole(text, "path number")
    try:
        return check_path(value)
    except ValueError as exc:
        raise ValueError(_as_typed(str(exc), text)) from None


def parse_one_of(text: str, choices: Sequence[int]) -> int:
    """A whole number of ``choices`` (``--width``: 1, 2 or 4), refused in ``argparse``'s
    words for a choice, naming the number as typed (``0x3``)."""
    value = fmt.parse_int(text)
    if value not in choices:
        listed = ", ".join(map(str, choices))
        raise ValueError(f"invalid choice: {text.strip()} (choose from {listed})")
    return value


def parse_history_depth(text: str) -> int:
    """How many alarm history entries to read: 1 or more, more than 250 read as 250, by the
    rule of both clients (:func:`~focas_net.client._values.history_depth`)."""
    value = _whole(text, "history depth")
    try:
        return history_depth(value)
    except ValueError as exc:
        raise ValueError(_as_typed(str(exc), text)) from None


def parse_area(text: str) -> PmcArea:
    """A PMC area by letter (``R``) or number; ValueError naming the areas otherwise, in the
    words of every front end (:meth:`PmcArea.parse`)."""
    return PmcArea.parse(text)


#: The thresholds ``--log-level`` takes (``logging``'s level names).
LOG_LEVELS: Final = ("DEBUG", "INFO", "WARNING", "ERROR", "CRITICAL")


def parse_log_level(text: str) -> str:
    """A logging threshold of :data:`LOG_LEVELS`, in any case (``info``); its refusal names
    the text as typed."""
    level = text.strip().upper()
    if level not in LOG_LEVELS:
        raise ValueError(
            f"invalid choice: {text!r} (choose from {', '.join(LOG_LEVELS)}, in any case)"
        )
    return level


#: A port to connect to, 1..65535.
PORT: Final = argument_type(parse_port, "port")
#: A port to listen on, 0..65535 (0: an ephemeral port).
LISTEN_PORT: Final = argument_type(partial(parse_port, lowest=0), "port")
INT: Final = argument_type(fmt.parse_int, "integer")
POSITIVE: Final = argument_type(parse_positive, "count")
NON_NEGATIVE: Final = argument_type(parse_non_negative, "count")
#: ``--axis`` of a parameter and of a diagnostic (0: not an axis item).
PARAM_AXIS: Final = argument_type(partial(parse_item_axis, "parameter"), "axis")
DIAG_AXIS: Final = argument_type(partial(parse_item_axis, "diagnostic"), "axis")
#: ``--axis`` of ``sim alarm`` (0: an alarm of no axis).
ALARM_AXIS: Final = argument_type(parse_alarm_axis, "axis")
#: An override of ``sim override`` (its option: ``--feed``, ``--rapid``, ``--spindle``).
FEED: Final = argument_type(partial(parse_override, "feed"), "feed override")
RAPID: Final = argument_type(partial(parse_override, "rapid"), "rapid override")
SPINDLE: Final = argument_type(partial(parse_override, "spindle"), "spindle override")
FILE_NAME: Final = argument_type(parse_file_name, "file name")
SECONDS: Final = argument_type(parse_seconds, "seconds")
INTERVAL: Final = argument_type(parse_interval, "seconds")
HOST: Final = argument_type(parse_host, "host")
#: A host to listen on (``serve --host``): one typed with a port points to ``--port``, 0 too.
LISTEN_HOST: Final = argument_type(partial(parse_host, lowest=0), "host")
BOOL: Final = argument_type(fmt.parse_bool, "on/off")
#: A value's width in bytes (``param set --width``).
WIDTH: Final = argument_type(partial(parse_one_of, choices=(1, 2, 4)), "width")
AREA: Final = argument_type(parse_area, "area")
HISTORY_DEPTH: Final = argument_type(parse_history_depth, "depth")
PATH: Final = argument_type(parse_path, "path")
LOG_LEVEL: Final = argument_type(parse_log_level, "log level")
#: A parameter password (``--password``, ``unlock PASSWORD``, ``serve --param-password``).
PASSWORD: Final = argument_type(parse_password, "password")
