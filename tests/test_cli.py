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


# --- reports diff: a missing or unreadable report is a difference --------------------------------------------------


def _git(cwd, *args):
    subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args], cwd=cwd, check=True,
                   capture_output=True)


def _committed_reports(tmp_path, monkeypatch):
    """A checkout (params.yaml, two committed reports) as the working directory; returns a regenerated copy."""
    import shutil

    from navlab.metrics.tables import Table
    from navlab.pipeline.reports import write_table

    repo = tmp_path / "repo"
    repo.mkdir()
    shutil.copy("params.yaml", repo / "params.yaml")
    for table in ("table1_seen", "table2_unseen"):
        write_table(repo / "reports", Table(table, "Table", ["method", "low"], [{"method": "PACER", "low": 0.5}], [], ""),
                    track="pacer", profile="smoke", seeds=[0])
    _git(repo, "init", "-q")
    _git(repo, "add", ".")
    _git(repo, "commit", "-q", "-m", "reports")
    regenerated = tmp_path / "regenerated"
    shutil.copytree(repo / "reports", regenerated)
    monkeypatch.chdir(repo)
    return regenerated


def test_reports_diff_of_identical_reports_passes(tmp_path, monkeypatch, capsys):
    regenerated = _committed_reports(tmp_path, monkeypatch)
    assert main(["reports", "diff", "--reports-dir", str(regenerated)]) == 0
    assert "2 tables compared with HEAD: 0 numbers moved, 0 reports missing or unreadable" in capsys.readouterr().out


def test_reports_diff_counts_missing_and_unreadable_reports(tmp_path, monkeypatch, capsys):
    regenerated = _committed_reports(tmp_path, monkeypatch)
    (regenerated / "pacer" / "table1_seen.json").unlink()
    truncated = regenerated / "pacer" / "table2_unseen.json"
    truncated.write_text(truncated.read_text()[:40])
    assert main(["reports", "diff", "--reports-dir", str(regenerated)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert f"reports/pacer/table1_seen.json: missing in {regenerated}/" in out
    assert any(line.startswith(f"{truncated}: not readable JSON (") for line in out)
    assert out[-1] == "0 tables compared with HEAD: 0 numbers moved, 2 reports missing or unreadable"
    assert not any("Traceback" in line for line in out)


# --- a full disk or read-only folder: one line naming the path, exit 2 ---------------------------------------------


def test_report_write_on_a_full_disk_is_one_line(tmp_path, monkeypatch, capsys):
    import errno
    from pathlib import Path

    from navlab.metrics.tables import Table
    from navlab.pipeline.reports import write_table

    write_table(tmp_path, Table("table1_seen", "Table", ["method", "low"], [{"method": "PACER", "low": 0.5}], [], ""),
                track="pacer", profile="smoke", seeds=[0])

    def full(self, data):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Path, "write_bytes", full)
    assert main(["reports", "index", "--reports-dir", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{tmp_path / 'README.md'}: No space left on device" in err
    assert not (tmp_path / "README.md").exists()


def test_data_build_on_a_read_only_disk_is_one_line(tmp_path, monkeypatch, capsys):
    import errno

    from navlab import cli

    def raw(params, out):
        raise OSError(errno.EROFS, "Read-only file system")  # as a failed write: no file name

    raw.__module__ = "navlab.pipeline.sources"
    monkeypatch.setattr(cli, "data_steps", lambda: [("raw", raw)])
    assert main(["data", "build", "--profile", "smoke", "--data-dir", str(tmp_path / "data")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{tmp_path / 'data.partial'}: Read-only file system" in err


def test_other_os_errors_still_raise(monkeypatch):
    from navlab import cli

    def broken(args):
        raise FileNotFoundError(2, "No such file or directory", "x")

    monkeypatch.setattr(cli, "_params_show", broken)
    with pytest.raises(FileNotFoundError):
        main(["params", "show"])


# --- lab passes every option to jupyter lab ------------------------------------------------------------------------


def test_lab_passes_its_options_to_jupyter(monkeypatch):
    import os

    started = []
    monkeypatch.setattr(os, "execv", lambda path, cmd: started.append(cmd))
    main(["lab", "--port", "9999", "--no-browser"])
    assert started[0][-3:] == ["--port", "9999", "--no-browser"]
    assert started[0][1:4] == ["-m", "jupyter", "lab"]


def test_lab_options_parse_without_starting_jupyter():
    from navlab.cli import parse_args

    assert parse_args(["lab", "--port", "9999"]).options == ["--port", "9999"]
    assert parse_args(["lab", "--ServerApp.port=0", "nb.ipynb"]).options == ["--ServerApp.port=0", "nb.ipynb"]
    assert parse_args(["lab"]).options == []
