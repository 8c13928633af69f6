"""Command ids of the packed protocol (``docs/protocol.md`` section 3); append-only, never
renumber."""

from __future__ import annotations

import enum

__all__ = ["FAULT_COMMANDS", "PATH_COMMANDS", "PATH_INDEPENDENT_COMMANDS", "Command"]


class Command(enum.IntEnum):
    """Command ids. The FOCAS name each one stands for is in its comment."""

    RDCNCSTAT = 0x0001  # cnc_rdcncstat [cnc_statinfo]: ODBST
    RDPARAM = 0x0002  # cnc_rdparam: IODBPSD
    RDMACRO = 0x0003  # cnc_rdmacro: ODBM
    RDDIAG = 0x0004  # cnc_rddiag [cnc_diagnoss]
    SYSINFO = 0x0005  # cnc_sysinfo: ODBSYS
    RDALMMSG = 0x0006  # cnc_rdalmmsg: active alarms
    RDPRGNUM = 0x0007  # cnc_rdprgnum: running and main program numbers
    ACTF = 0x0008  # cnc_actf: actual feed rate
    ACTS = 0x0009  # cnc_acts: actual spindle speed
    RDPOSITION = 0x000A  # cnc_rdposition: positions in least input increments
    RDPMCRNG = 0x0010  # pmc_rdpmcrng: IODBPMC
    RDPARAINFO = 0x0020  # cnc_rdparainfo: a parameter's type, axis flag, decimals and range
    RDPROGDIR = 0x0030  # cnc_rdprogdir: the program directory
    RDPROGRAM = 0x0031  # cnc_upload: a program's text
    RDRUNINFO = 0x0032  # overrides, parts counts and timers [cnc_rdtimer]
    RDLOADS = 0x0033  # cnc_rdspload and cnc_rdsvmeter: spindle and servo loads
    GETPATH = 0x0040  # cnc_getpath: the connection's selected path and the number of paths
    WRPARAM = 0x0102  # cnc_wrparam: IODBPSD
    WRMACRO = 0x0103  # cnc_wrmacro: ODBM
    WRPMCRNG = 0x0104  # pmc_wrpmcrng: IODBPMC
    WRUNLOCKPARAM = 0x0105  # cnc_wrunlockparam
    WRPROGRAM = 0x0110  # cnc_download: store a program
    DELPROGRAM = 0x0111  # cnc_delete: delete a program
    SELPROGRAM = 0x0112  # cnc_search: select the main program
    SETPATH = 0x0140  # cnc_setpath: select the path the connection's per-path requests read
    VERSAMAX_RDCONFIG = 0x0201  # VersaMax GNIU Read Configuration datagram
    SIM_SET_PANEL = 0x0E01  # simulator control: operator panel
    SIM_RAISE_ALARM = 0x0E02  # simulator control: raise an alarm
    SIM_CLEAR_ALARMS = 0x0E03  # simulator control: clear active alarms
    SIM_SET_PMC = 0x0E04  # simulator control: write PMC ignoring protection
    SIM_INJECT_FAULT = 0x0E05  # simulator control: fault injection
    SIM_LIST_FAULTS = 0x0E06  # simulator control: the pending faults of one scope
    SIM_CLEAR_FAULTS = 0x0E07  # simulator control: remove the pending faults of one scope
    SIM_READ_PANEL = 0x0E10  # simulator control: read the operator panel
    SIM_VACATE_MACRO = 0x0E11  # simulator control: make a macro variable vacant
    SIM_CYCLE = 0x0E20  # simulator control: cycle start, feed hold, reset
    SIM_SET_OVERRIDES = 0x0E21  # simulator control: feed, rapid and spindle override
    RDALMHISTRY = 0x0F1A  # cnc_rdalmhistry: ODBAHIS


#: The fault-queue commands, answered by the server's connections (which hold the queues), not
#: by a machine's adapter.
FAULT_COMMANDS: frozenset[Command] = frozenset(
    {Command.SIM_INJECT_FAULT, Command.SIM_LIST_FAULTS, Command.SIM_CLEAR_FAULTS}
)


#: The path selection commands (``docs/protocol.md`` section 8, "Paths"), answered from the
#: connection's selection; never faulted, like the simulator control commands.
PATH_COMMANDS: frozenset[Command] = frozenset({Command.GETPATH, Command.SETPATH})

#: The commands that answer the same on every path and ignore the connection's path
#: selection: the identity, the PMC, the parameter attributes, the alarm
#: history, the parameter unlock, VersaMax, the fault queues and the path commands
#: themselves. Every other command answers for the connection's selected path.
PATH_INDEPENDENT_COMMANDS: frozenset[Command] = frozenset(
    {
        Command.SYSINFO,
        Command.RDPMCRNG,
        Command.RDPARAINFO,
        Command.WRPMCRNG,
        Command.WRUNLOCKPARAM,
        Command.VERSAMAX_RDCONFIG,
        Command.SIM_SET_PMC,
        Command.RDALMHISTRY,
        *FAULT_COMMANDS,
        *PATH_COMMANDS,
    }
)
