"""Shell completion as docs/cli.md describes it: click answers for ``taxelkit``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(sys.executable).with_name("taxelkit")
pytestmark = pytest.mark.skipif(not SCRIPT.exists(), reason="the console script is not installed")


def _complete(mode: str, words: str = "", cword: int = 0) -> str:
    env = {**os.environ, "_TAXELKIT_COMPLETE": mode, "COMP_WORDS": words, "COMP_CWORD": str(cword)}
    done = subprocess.run([str(SCRIPT)], env=env, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.mark.parametrize("shell", ["bash", "zsh", "fish"])
def test_the_documented_source_commands_print_a_script(shell: str) -> None:
    script = _complete(f"{shell}_source")
    assert "_taxelkit_completion" in script
    assert "_TAXELKIT_COMPLETE" in script


def test_sub_commands_and_choices_complete() -> None:
    assert _complete("bash_complete", "taxelkit rec", 1).split() == ["plain,recognize"]
    words = _complete("bash_complete", "taxelkit simulate ", 2).split()
    assert words == ["plain,press", "plain,roll", "plain,solid"]
