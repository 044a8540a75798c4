import subprocess
import sys

import pytest

from navlab.cli import build_parser, main


def _run(*args):
    return subprocess.run([sys.executable, "-m", "navlab", *args], capture_output=True, text=True, check=False)


def test_every_subcommand_has_help():
    parser = build_parser()
    groups = parser._subparsers._group_actions[0].choices
    for name, group in groups.items():
        cmds = group._subparsers._group_actions[0].choices if group._subparsers else [None]  # `lab`: no cmds
        for cmd in cmds:
            with pytest.raises(SystemExit) as exit_:
                main([name, *filter(None, [cmd]), "--help"])
            assert exit_.value.code == 0


def test_bad_params_is_one_line_error(tmp_path, monkeypatch):
    with open("params.yaml") as fh:
        (tmp_path / "params.yaml").write_text(fh.read().replace("queries:", "querys:"))
    monkeypatch.chdir(tmp_path)
    proc = _run("params", "show")
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0
    assert "quickstart.querys: unknown key" in proc.stderr


def test_missing_data_says_which_command_builds_it(tmp_path):
    proc = _run("data", "verify", "--data-dir", str(tmp_path / "nothing"))
    assert proc.returncode == 1
    assert "python -m navlab data build" in proc.stdout
