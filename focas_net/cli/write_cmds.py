"""The writing commands: ``param set``, ``macro set``, ``pmc write``, ``pmc bit`` and
``unlock``; each reads back what it wrote."""

from __future__ import annotations

import argparse
from typing import Final

from focas_net._typed import NO_PASSWORD_NOTE
from focas_net.client import CncClient, FocasClient
from focas_net.client._failures import command_text
from focas_net.client._values import (
    check_int,
    check_macro,
    check_pmc_range,
    macro_write,
    pmc_data,
)
from focas_net.errors import AccessDeniedError, CncError
from focas_net.protocol import Command, PmcArea, pmc_bit_refusal

from . import _format as fmt
from ._args import ArgumentRefused, named, note_typed, typed_number_bit
from ._run import Go, Output, PackedOnly
from .read_cmds import (
    PMC_LAST,
    axis_hint,
    macro_dict,
    param_kind,
    param_number,
    param_output,
)

__all__ = ["macro_clear", "macro_set", "param_set", "pmc_bit", "pmc_write", "unlock"]


def param_set(args: argparse.Namespace) -> Go:
    number, bit = param_number(args)
    if bit is not None:
        if args.width is not None:
            raise ArgumentRefused("--width", "does not apply to a bit write (NUMBER.BIT)")
        bit_value = named("VALUE", fmt.parse_bool, args.value)
    else:
        value = named("VALUE", fmt.parse_param_value, args.value)
        note_typed(args, value, args.value)  # (0x80000000 named as typed if refused)

    async def go(cnc: CncClient) -> Output:
        try:
            if bit is None:
                await cnc.write_param(number, value, axis=args.axis, width=args.width)
            else:
                await cnc.write_param_bit(number, bit, bit_value, axis=args.axis)
        except CncError as exc:
            raise await axis_hint(cnc, exc, "parameter", number, args.axis) from exc
        pv = await cnc.read_param_value(number, axis=args.axis)
        kind = await param_kind(cnc, number, pv)
        data, whole, bit_text = param_output(number, bit, args.axis, pv, kind)
        text = whole if bit_text is None else f"{bit_text}; {whole}"
        return Output(data, f"{text} (written)")

    return go


def macro_set(args: argparse.Namespace) -> Go:
    # a number or a value no CNC's field carries is refused before connecting (exit 2)
    named("NUMBER", check_macro, args.number)
    named("VALUE", macro_write, args.number, args.value)  # (its words name the variable)

    async def go(cnc: CncClient) -> Output:
        await cnc.write_macro(args.number, args.value)
        value = await cnc.read_macro(args.number)
        return Output(
            macro_dict(args.number, value),
            f"#{args.number} = {fmt.macro_text(value)} (written)",
        )

    return go


def macro_clear(args: argparse.Namespace) -> PackedOnly:
    named("NUMBER", check_macro, args.number)

    # a simulator control command (sim_vacate_macro): a real CNC answers EW_FUNC
    async def go(cnc: FocasClient) -> Output:
        await cnc.sim.vacate_macro(args.number)
        value = await cnc.read_macro(args.number)
        return Output(
            macro_dict(args.number, value),
            f"#{args.number} = {fmt.macro_text(value)} (cleared)",
        )

    return PackedOnly(
        go,
        "vacating a variable is a simulator control command, "
        + command_text(Command.SIM_VACATE_MACRO),
    )


def pmc_write(args: argparse.Namespace) -> Go | PackedOnly:
    area: PmcArea = args.area
    if args.hex is not None and args.values:
        raise ArgumentRefused(
            "--hex", "not allowed with BYTE values: give the bytes either as values or with --hex"
        )
    if args.hex is not None:
        payload = named("--hex", fmt.parse_hex, args.hex)
    else:
        payload = named("BYTE", fmt.parse_byte_list, args.values)
    named("START", check_int, "PMC start address", args.start, 0, PMC_LAST)
    pmc_data(args.start, payload)  # (where the bytes end: both arguments)

    def written() -> Output:
        last = args.start + len(payload) - 1
        data = {"area": area.name, "start": args.start, "count": len(payload), "hex": payload.hex()}
        where = f"{area.name}{args.start}" + (f"..{area.name}{last}" if last > args.start else "")
        return Output(
            data,
            f"wrote {len(payload)} byte{'s' * (len(payload) > 1)} to {where}: "
            + fmt.bytes_summary(payload),
        )

    async def force(cnc: FocasClient) -> Output:
        await cnc.sim.set_pmc(area, args.start, payload)
        return written()

    async def go(cnc: CncClient) -> Output:
        await cnc.write_pmc(area, args.start, payload)
        return written()

    if args.force:
        return PackedOnly(
            force,
            "--force writes through a simulator control command, "
            + command_text(Command.SIM_SET_PMC),
            "--force",
        )
    return go


def _parse_byte_bit(args: argparse.Namespace, area: PmcArea, text: str) -> tuple[int, int]:
    expected = "BYTE.BIT (e.g. 100.3)"
    byte, bit = named(_BYTE_BIT, typed_number_bit, args, text, expected)
    if bit is None:
        raise ArgumentRefused(_BYTE_BIT, f"expected {expected}, got {text!r}")
    why = pmc_bit_refusal(area.name, byte, bit)  # the words of every front end (-1 too)
    if why is not None:
        raise ArgumentRefused(_BYTE_BIT, why)
    named(_BYTE_BIT, check_pmc_range, byte, 1)
    return byte, bit


#: ``pmc bit``'s address, as ``--help`` names it.
_BYTE_BIT: Final = "BYTE.BIT"


def pmc_bit(args: argparse.Namespace) -> Go:
    area: PmcArea = args.area
    byte, bit = _parse_byte_bit(args, area, args.address)
    value: bool | None = args.value  # read by the parser (argument VALUE)

    async def go(cnc: CncClient) -> Output:
        if value is not None:
            await cnc.write_pmc_bit(area, byte, bit, value)
        current = await cnc.read_pmc_bit(area, byte, bit)
        data = {"area": area.name, "byte": byte, "bit": bit, "value": int(current)}
        suffix = " (written)" if value is not None else ""
        return Output(data, f"{area.name}{byte}.{bit} = {int(current)}{suffix}")

    return go


def unlock(args: argparse.Namespace) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        await cnc.unlock(args.secret)
        # A CNC without a password accepts any; with one, only that one: a second, other
        # password tells which (the unlock ends with the command's connection anyway).
        try:
            await cnc.unlock("1" if args.secret == "0" else "0")
        except AccessDeniedError:
            return Output(
                {"unlocked": True, "password_set": True},
                "password accepted (an unlock holds for one connection: give --password to "
                "the commands that write parameters)",
            )
        return Output(
            {"unlocked": True, "password_set": False},
            NO_PASSWORD_NOTE,
        )

    return PackedOnly(go, "FOCAS/2 has no cnc_wrunlockparam")
