"""Program text and the program store: tape marks, blocks, comments, sequence numbers, block
delete, the decimal point rule, and the store's checks."""

from __future__ import annotations

import pytest

from focas_net.sim.nc import ProgramError, ProgramErrorReason, ProgramStore, parse_program
from focas_net.sim.nc.macro import Num
from focas_net.sim.nc.program import Bad, Words

TAPE = (
    "junk before\n%\nO0123 (BRACKET)\nN10 G90 G21 (SAFE) ;N20 G0 X10. Y5\n/N30 M8\n\n%\ntrailer\n"
)


def test_tape_marks_blocks_comments_and_sequence_numbers() -> None:
    program = parse_program(TAPE)
    assert (program.number, program.name) == (123, "BRACKET")
    assert [b.sequence for b in program.blocks] == [10, 20, 30]
    first, second, third = program.blocks
    assert first.comment == "SAFE"
    assert not first.deletable and third.deletable
    assert isinstance(second.statement, Words)
    x, y = second.statement.words[1:]
    assert (x.address, x.value, x.integer_literal) == ("X", Num(10.0), False)
    assert (y.address, y.value, y.integer_literal) == ("Y", Num(5.0), True)
    assert program.text.splitlines()[0] == "O0123 (BRACKET)"
    assert "trailer" not in program.text and "junk" not in program.text


def test_lower_case_and_spaces_are_read() -> None:
    program = parse_program("o7\ng 0 1 x - 1 2 . 5 f100\n")
    words = program.blocks[0].statement
    assert isinstance(words, Words)
    assert [(w.address, w.value) for w in words.words] == [
        ("G", Num(1.0)),
        ("X", Num(-12.5)),
        ("F", Num(100.0)),
    ]


def test_a_malformed_block_is_kept_with_its_alarm() -> None:
    program = parse_program("O1\nN5 G1 X\nM30\n")
    bad = program.blocks[0].statement
    assert isinstance(bad, Bad) and bad.alarm == 5
    assert program.blocks[0].sequence == 5


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("", ProgramErrorReason.FORMAT),
        ("G90 G0 X1.\n", ProgramErrorReason.FORMAT),
        ("O\nM30\n", ProgramErrorReason.FORMAT),
        ("O0\nM30\n", ProgramErrorReason.RANGE),
        ("O10000\nM30\n", ProgramErrorReason.RANGE),
    ],
)
def test_texts_that_are_no_program(text: str, reason: ProgramErrorReason) -> None:
    with pytest.raises(ProgramError) as info:
        parse_program(text)
    assert info.value.reason is reason
    if text.strip():
        assert text.split("\n")[0][:3] in str(info.value)


@pytest.mark.parametrize(
    "text",
    [
        "O1234\nG0 X1.\nM30\n%",  # the closing mark alone
        "O1234\nG0 X1.\nM30\n%\n",
        "\n%\nO1234\nG0 X1.\nM30\n%\n",  # both marks
        "%\nO1234\nG0 X1.\nM30\n",  # the opening mark alone
        "leader\n%\nO1234\nG0 X1.\nM30\n%\n(trailer)\n",
        "O1234\r\nG0 X1.\r\nM30\r\n%\r\n%\r\n",
    ],
)
def test_a_program_between_or_before_its_tape_marks(text: str) -> None:
    assert parse_program(text).text == "O1234\nG0 X1.\nM30\n"


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("O1\nM30\nO2\nM30\n", "line 3: 'O2' starts a second program: one program per text"),
        ("O1\nM30\n:2 (B)\nM30\n", "line 3: ':2 (B)' starts a second program"),
        ("O1\nM30\n%\nO2\nM30\n%\n", "line 4: 'O2' starts a second program after the closing %"),
        (
            "%\nO1\nM30\n%\n\no2\nM30\n%\n",
            "line 6: 'o2' starts a second program after the closing % (line 4)",
        ),
    ],
)
def test_a_second_program_in_one_text_is_refused(text: str, words: str) -> None:
    """One text holds one program: a second one would be lost, never silently run as blocks
    of the first or dropped as a trailer."""
    with pytest.raises(ProgramError) as info:
        parse_program(text)
    assert info.value.reason is ProgramErrorReason.FORMAT
    assert words in str(info.value)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("O1 (\x07BELL)\nM30\n", "line 1: character '\\x07' (U+0007)"),
        ("O1 (\u00c4NDERUNG)\nM30\n", "line 1: character '\u00c4' (U+00C4)"),
        ("O1\nG0 X1.\x1b\nM30\n", "line 2: character '\\x1b' (U+001B)"),
        ("O1\nG0 X1.\x00\nM30\n", "line 2: character '\\x00' (U+0000)"),
    ],
)
def test_a_program_is_printable_ascii(text: str, words: str) -> None:
    """A program name or block with a control character or a character beyond ASCII is
    refused by the store every front end loads through, naming its line."""
    with pytest.raises(ProgramError) as info:
        parse_program(text)
    assert info.value.reason is ProgramErrorReason.FORMAT
    assert words in str(info.value) and "a program is printable ASCII text" in str(info.value)


def test_tabs_and_the_nuls_ending_a_c_string_are_read() -> None:
    assert parse_program("O1\n\tG0\tX1.\nM30\n%\x00\x00").text == "O0001\nG0\tX1.\nM30\n"


def test_the_store_lists_gets_stores_deletes_and_selects() -> None:
    store = ProgramStore()
    store.store("O2 (B)\nM30\n")
    store.store("O1 (A)\nG0 X1.\nM30\n")
    assert [(p.number, p.name) for p in store.directory()] == [(1, "A"), (2, "B")]
    assert store.text(2) == "O0002 (B)\nM30\n"
    version = store.version
    store.select(2)
    assert store.main == 2 and store.version > version
    store.delete(2)
    assert store.main is None and 2 not in store and len(store) == 1


def test_the_store_refuses_what_a_cnc_refuses() -> None:
    store = ProgramStore(max_programs=2, capacity=40)
    store.store("O1\nM30\n")
    with pytest.raises(ProgramError) as info:
        store.store("O1\nM2\n")
    assert (info.value.reason, info.value.alarm) == (ProgramErrorReason.DUPLICATE, 73)
    assert "O0001" in str(info.value)
    assert store.store("O1\nM2\n", replace=True).blocks[0].text == "M2"
    with pytest.raises(ProgramError) as info:
        store.store("O3\n" + "G0 X1.\n" * 10)
    assert info.value.reason is ProgramErrorReason.NO_SPACE
    store.store("O4\nM30\n")
    with pytest.raises(ProgramError) as info:
        store.store("O5\nM30\n")
    assert info.value.reason is ProgramErrorReason.TOO_MANY
    for action in (store.get, store.delete, store.select, store.text):
        with pytest.raises(ProgramError) as info:
            action(99)
        assert info.value.reason is ProgramErrorReason.NOT_FOUND and "O0099" in str(info.value)


def test_loops_are_paired_when_stored() -> None:
    program = parse_program("O1\nWHILE [1] DO1\nDO2\nEND2\nEND1\nEND3\nDO1\n")
    assert program.loops[0] == 3 and program.loops[1] == 2
    assert program.loop_errors[4][0] == 124  # END3 without DO3
    assert program.loop_errors[5][0] == 124  # DO1 without END1
