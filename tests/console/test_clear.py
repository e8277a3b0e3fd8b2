"""``clear`` clears the screen as a shell does (issue 42, item 3.3); the interactive side, where
the prompt comes back at the top, is in tests/console/test_interactive.py."""

from __future__ import annotations

from ddes.console.shell import CLEAR_KEEP_SCROLLBACK, CLEAR_SCREEN, Console


def test_clear_writes_the_ansi_codes_of_clear(console: Console) -> None:
    assert CLEAR_SCREEN == "\x1b[H\x1b[2J\x1b[3J"  # `TERM=xterm clear | od -c`
    assert CLEAR_KEEP_SCROLLBACK == "\x1b[H\x1b[2J"  # `clear -x`
    assert console.run("clear") == CLEAR_SCREEN + "\n"  # in a transcript, a line of codes
    assert console.run("clear -x") == CLEAR_KEEP_SCROLLBACK + "\n"
    result = console.execute("clear -q")
    assert (result.code, result.out) == (1, "")
    assert result.err == ("ERROR: clear: unknown option '-q' (usage: clear [-x]; -x keeps the "
                          "scrollback)\n")
    assert "clear" in console.commands() and "clear" in console.complete("cl", "cl")
    assert console.run("help clear") == "clear: a console command (see 'help')\n"
