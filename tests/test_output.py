"""-o and --plot never clobber what is at the path (issue 12): special files are written through, symlinks
are followed, modes are kept, inputs are protected, environmental write errors are exit 74.

Every test writes inside its own tmp_path only; device nodes are private (mknod, root only)."""
import errno
import os
import shutil
import stat
import subprocess
import sys
import threading

import pytest

from conftest import CONFIGS, cli, cli_proc

FIG3 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"
root_only = pytest.mark.skipif(os.geteuid() != 0, reason="mknod and chown need root")


def reference_csv():
    r = cli("rows", FIG3, "-f", "csv")
    assert r.code == 0 and r.out.startswith("name,")
    return r.out


def files_in(folder):
    return sorted(p.name for p in folder.iterdir())


@root_only
def test_private_null_device_stays_a_device(tmp_path):
    null = tmp_path / "null"
    os.mknod(null, stat.S_IFCHR | 0o666, os.makedev(1, 3))
    r = cli("rows", FIG3, "-f", "csv", "-o", null)
    assert r.code == 0, r
    assert stat.S_ISCHR(os.lstat(null).st_mode) and os.lstat(null).st_rdev == os.makedev(1, 3)
    assert files_in(tmp_path) == ["null"]  # no temporary file beside it


def _reader(fifo, sink):
    with open(fifo, "rb") as fh:
        sink.append(fh.read())


def test_fifo_receives_the_whole_csv(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=_reader, args=(fifo, got), daemon=True)
    reader.start()
    try:
        r = cli_proc("rows", FIG3, "-f", "csv", "-o", fifo)  # subprocess: bounded by its timeout
    finally:
        reader.join(timeout=30)
        if reader.is_alive():  # the writer never opened it: release the reader
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
            reader.join(timeout=5)
    assert r.code == 0, r
    assert got and got[0].decode() == reference_csv()
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert files_in(tmp_path) == ["pipe"]


def test_symlink_stays_a_symlink_and_its_target_gets_the_content(tmp_path):
    (tmp_path / "data").mkdir()
    target = tmp_path / "data" / "real.csv"
    target.write_text("old\n")
    first = tmp_path / "link1.csv"
    first.symlink_to(target)
    link = tmp_path / "link.csv"  # a chain: link.csv -> link1.csv -> data/real.csv
    link.symlink_to("link1.csv")
    r = cli("rows", FIG3, "-o", link)
    assert r.code == 0, r
    assert link.is_symlink() and first.is_symlink() and os.readlink(link) == "link1.csv"
    assert target.read_text() == reference_csv()
    assert files_in(tmp_path / "data") == ["real.csv"]


def test_dangling_symlink_creates_its_target(tmp_path):
    link = tmp_path / "link.csv"
    link.symlink_to(tmp_path / "new.csv")
    r = cli("rows", FIG3, "-o", link)
    assert r.code == 0, r
    assert link.is_symlink() and (tmp_path / "new.csv").read_text() == reference_csv()
    bad = tmp_path / "bad.csv"
    bad.symlink_to(tmp_path / "no" / "such" / "x.csv")
    r = cli("rows", FIG3, "-o", bad)
    assert r.code == 2 and "symlink" in r.err and "does not exist" in r.err
    assert bad.is_symlink() and not (tmp_path / "no").exists()


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_new_file_mode_follows_the_umask(tmp_path, umask, mode):
    out = tmp_path / "r.csv"
    old = os.umask(umask)
    try:
        r = cli("rows", FIG3, "-o", out)
    finally:
        os.umask(old)
    assert r.code == 0, r
    assert stat.S_IMODE(out.stat().st_mode) == mode


def test_existing_file_keeps_its_mode(tmp_path):
    out = tmp_path / "r.csv"
    out.write_text("old\n")
    os.chmod(out, 0o664)
    old = os.umask(0o077)
    try:
        r = cli("rows", FIG3, "-o", out)
    finally:
        os.umask(old)
    assert r.code == 0, r
    assert stat.S_IMODE(out.stat().st_mode) == 0o664 and out.read_text() == reference_csv()
    assert files_in(tmp_path) == ["r.csv"]


@root_only
def test_existing_file_keeps_its_owner_as_root(tmp_path):
    out = tmp_path / "r.csv"
    out.write_text("old\n")
    os.chown(out, 4321, 4322)
    r = cli("rows", FIG3, "-o", out)
    assert r.code == 0, r
    st = out.stat()
    assert (st.st_uid, st.st_gid) == (4321, 4322) and out.read_text() == reference_csv()


def test_dash_is_standard_output(tmp_path):
    r = cli_proc("rows", FIG3, "-o", "-", cwd=tmp_path)
    assert r.code == 0, r
    assert r.out == reference_csv()  # piped: the pipe rule (CSV), not a format from the name "-"
    r = cli_proc("new", "rows", "-o", "-", cwd=tmp_path)
    assert r.code == 0 and "kind" in r.out
    assert files_in(tmp_path) == []  # no file named "-"


def test_output_naming_an_input_is_refused(tmp_path):
    design = tmp_path / "d.toml"
    design.write_text(FIG3.read_text())
    before = design.read_bytes()
    r = cli("rows", design, "-o", design)
    assert r.code == 2 and "input" in r.err and r.out == ""
    link = tmp_path / "alias.csv"
    link.symlink_to(design)
    r = cli("run", tmp_path, "-o", link)  # via a symlink, and through a folder's expansion
    assert r.code == 2 and "input" in r.err
    r = cli("sweep", design, "--vary", "rows.relative_width=2.0,2.4", "-o", design)
    assert r.code == 2 and "input" in r.err
    assert design.read_bytes() == before and link.is_symlink()


@pytest.mark.parametrize("command", [["run", "-"], ["rows", "-"], ["sweep", "-", "--vary", "rows.count=1,2"]])
def test_output_naming_the_file_on_standard_input_is_refused(tmp_path, command):
    # `gearcalc run - -o v.toml < v.toml`: the design comes through descriptor 0, the file behind it is protected
    design = tmp_path / "v.toml"
    design.write_text(FIG3.read_text())
    before = design.read_bytes()
    with open(design, "rb") as stdin:
        p = subprocess.run([sys.executable, "-m", "gearcalc", *command, "-o", str(design)], stdin=stdin,
                           capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "is the file read from standard input" in p.stderr, p.stderr
    assert design.read_bytes() == before and files_in(tmp_path) == ["v.toml"]
    with open(design, "rb") as stdin:  # another file as output: a normal run
        p = subprocess.run([sys.executable, "-m", "gearcalc", *command, "-o", str(tmp_path / "o.csv")], stdin=stdin,
                           capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr


@pytest.mark.parametrize("option", ["-o", "--plot"])
def test_empty_output_path_is_refused(tmp_path, option):
    # `-o "$UNSET"` must not quietly become standard output (the file the script wanted would be lost)
    extra = ["-o", tmp_path / "x.csv"] if option == "--plot" else []
    r = cli("run", FIG3, *extra, option, "")
    assert r.code == 2 and f"{option} '': empty output path" in r.err and r.out == ""
    assert files_in(tmp_path) == []


def test_trailing_slash_names_a_folder(tmp_path):
    # as the shell's `> new.csv/` ("Not a directory"): not a file new.csv, nor a replaced old.csv
    r = cli("run", FIG3, "-o", f"{tmp_path}/new.csv/")
    assert r.code == 2 and "not a directory" in r.err
    old = tmp_path / "old.csv"
    old.write_text("old\n")
    for name in (f"{old}/", f"{old}/."):
        r = cli("run", FIG3, "-o", name)
        assert r.code == 2 and "not a directory" in r.err
    assert files_in(tmp_path) == ["old.csv"] and old.read_text() == "old\n"


def test_read_only_file_is_not_replaced(tmp_path):
    # the shell's `>` cannot open a 0444 file for writing: gearcalc does not replace it either, judged by the mode
    # bits (so as root too, who could write it), before computing: exit 74, Permission denied
    out = tmp_path / "ro.csv"
    out.write_text("keep\n")
    out.chmod(0o444)
    for args in (["run", FIG3], ["sweep", FIG3, "--vary", "rows.count=1,2"], ["new", "rows"]):
        r = cli(*args, "-o", out)
        assert r.code == 74 and f"cannot write {out}: Permission denied" in r.err, r
    assert out.read_text() == "keep\n" and stat.S_IMODE(out.stat().st_mode) == 0o444
    assert files_in(tmp_path) == ["ro.csv"]
    out.chmod(0o644)  # writable again: replaced as before
    assert cli("run", FIG3, "-o", out).code == 0 and out.read_text() == reference_csv()


def test_too_long_file_name_is_refused_before_computing(tmp_path):
    # NAME_MAX (255 bytes on Linux): said before the designs are read (the missing design is never reported)
    name = "x" * 296 + ".csv"
    r = cli("run", tmp_path / "missing.toml", "-o", tmp_path / name)
    assert r.code == 2 and "file name too long (300 bytes" in r.err and "missing.toml" not in r.err, r
    longest = "y" * (os.pathconf(tmp_path, "PC_NAME_MAX") - 4) + ".csv"  # the longest name the folder holds
    r = cli("run", FIG3, "-o", tmp_path / longest)  # its temporary file's name is shortened to fit
    assert r.code == 0, r
    assert files_in(tmp_path) == [longest] and (tmp_path / longest).read_text() == reference_csv()


def test_output_and_plot_naming_the_same_file_is_refused(tmp_path):
    out = tmp_path / "x.png"
    r = cli("rows", FIG3, "-o", out, "--plot", out)
    assert r.code == 2 and "same file" in r.err
    assert files_in(tmp_path) == []


def test_plot_with_an_unknown_extension_names_the_formats(tmp_path):
    r = cli("rows", FIG3, "--plot", tmp_path / "fig.xyz")
    assert r.code == 2 and ".xyz" in r.err
    for ext in ("png", "pdf", "svg", "jpg", "webp"):
        assert ext in r.err
    assert r.out == "" and files_in(tmp_path) == []  # refused before computing


def test_plot_through_a_symlink_keeps_the_symlink(tmp_path):
    pytest.importorskip("matplotlib")
    target = tmp_path / "real.svg"
    target.write_text("old")
    os.chmod(target, 0o640)
    link = tmp_path / "fig.svg"
    link.symlink_to("real.svg")
    r = cli("rows", FIG3, "-f", "csv", "--plot", link)
    assert r.code == 0, r
    assert link.is_symlink() and b"<svg" in target.read_bytes()
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert files_in(tmp_path) == ["fig.svg", "real.svg"]


@root_only
def test_private_dev_full_is_exit_74_with_the_reason(tmp_path):
    full = tmp_path / "full"
    os.mknod(full, stat.S_IFCHR | 0o666, os.makedev(1, 7))
    r = cli("rows", FIG3, "-o", full)
    assert r.code == 74
    assert f"cannot write {full}: No space left on device" in r.err and "internal error" not in r.err
    assert stat.S_ISCHR(os.lstat(full).st_mode)


@root_only
@pytest.mark.parametrize("args", [pytest.param(["run", CONFIGS], marks=pytest.mark.slow),  # every config: long
                                  ["new", "rows"], ["rows", FIG3]])
def test_standard_output_on_a_full_device_is_exit_74(tmp_path, args):
    # `gearcalc run configs > /dev/full`, with a private /dev/full (the error may come at the final flush)
    full = tmp_path / "full"
    os.mknod(full, stat.S_IFCHR | 0o666, os.makedev(1, 7))
    with open(full, "w") as sink:
        p = subprocess.run([sys.executable, "-m", "gearcalc", *map(str, args)], stdout=sink,
                           stderr=subprocess.PIPE, text=True, timeout=300)
    assert p.returncode == 74, p.stderr[-500:]
    assert "cannot write standard output: No space left on device" in p.stderr
    assert "internal error" not in p.stderr and "Traceback" not in p.stderr


def test_read_only_failure_keeps_the_old_file_and_leaves_no_temporary(tmp_path, monkeypatch):
    out = tmp_path / "r.csv"
    out.write_bytes(b"old contents\n")

    def refuse(*a, **k):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(os, "replace", refuse)
    r = cli("rows", FIG3, "-o", out)
    assert r.code == 74, r
    assert f"cannot write {out}: Read-only file system" in r.err
    assert out.read_bytes() == b"old contents\n"
    assert files_in(tmp_path) == ["r.csv"]


def test_disk_full_while_writing_leaves_no_temporary(tmp_path, monkeypatch):
    out = tmp_path / "r.json"

    def full(fd, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "write", full)
    r = cli("rows", FIG3, "-o", out)
    assert r.code == 74 and "No space left on device" in r.err
    assert files_in(tmp_path) == []


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
def test_process_substitution(tmp_path):
    out = tmp_path / "out.csv"
    script = f'"{sys.executable}" -m gearcalc rows "{FIG3}" -o >(cat > "{out}"); code=$?; wait $!; exit $code'
    p = subprocess.run(["bash", "-c", script], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert out.read_text() == reference_csv()


def test_stdout_takes_a_bytearray(capsysbinary):
    # a streamed sweep's CSV piece is a bytearray (gearcalc.render._csv_rows_vectorised): written as bytes
    from gearcalc.output import write_stdout

    write_stdout(bytearray(b"a,b\n1,2\n"))
    write_stdout(memoryview(b"3,4\n"))
    assert capsysbinary.readouterr().out == b"a,b\n1,2\n3,4\n"


def test_a_file_written_in_pieces_has_its_writeback_started_as_it_grows(tmp_path, monkeypatch):
    # a streamed sweep's file: the system is asked to start writing each WRITEBACK_BYTES to disk (the fsync at the
    # end then waits for little); the content and the atomic replacement are unchanged
    from gearcalc import output

    monkeypatch.setattr(output, "WRITEBACK_BYTES", 1000)
    calls = []
    start = output.start_writeback
    monkeypatch.setattr(output, "start_writeback", lambda fd, at, n: calls.append((at, n)) or start(fd, at, n))
    path = tmp_path / "big.csv"
    path.write_bytes(b"old")
    pieces = [bytes([65 + k]) * 700 for k in range(5)]
    with output.stream(str(path)) as out:
        for piece in pieces:
            out.write(piece)
        assert path.read_bytes() == b"old"
    assert path.read_bytes() == b"".join(pieces)
    assert calls == [(0, 1400), (1400, 1400)]
    assert files_in(tmp_path) == ["big.csv"]


def test_start_writeback_where_the_system_has_it(tmp_path):
    from gearcalc import output

    fd = os.open(tmp_path / "f", os.O_WRONLY | os.O_CREAT, 0o644)
    try:
        os.write(fd, b"x" * 10000)
        assert output.start_writeback(fd, 0, 10000) == sys.platform.startswith("linux")
    finally:
        os.close(fd)
