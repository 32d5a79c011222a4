"""One reader guard for every file the core reads (issue 36): ``windpump.readers.files.read_bytes``.

Every reader of a user's file (a site's weather, a wind CSV, a lab torque file, a design file or a
table of designs on the command line) takes bytes (the contents) or a path, and goes through the
guard: a regular file only (a pipe, a folder or a device refused without waiting on it), at most
``max_bytes`` read, and a path that cannot be one (a NUL byte, longer than a path can be, a file's
contents passed as a ``str``) refused in words that name the parameter, show at most ~80 characters
of it and say the limit. A wind CSV near the size limit is read in memory a small multiple of its
size. A FIFO without a writer used to block ``read_weather`` (and ``windpump supply --weather``)
for ever: the tests that open one carry a timeout, so a regression fails instead of hanging.
"""

from __future__ import annotations

import datetime
import os
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

import windpump
from windpump import LabDataError, ParameterError, cli, cliargs, files
from windpump.model.wind import read_csv
from windpump.readers.labdata import read_torque_csv
from windpump.sites.weather import read_weather

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="POSIX pipes and devices")

LAB = b"10,0.2\n50,0.6\n90,0.2\n"
WIND = b"time,speed\n0,4\n3600,5\n7200,6\n"
# Each reader of a user's file, with contents it reads
READERS = {
    "weather": (read_weather, WIND),
    "wind csv": (read_csv, WIND),
    "lab csv": (read_torque_csv, LAB),
    "design file": (lambda source: cli.read_text(source, "--design"), b"{}"),
}
PACKAGE_ERRORS = (ParameterError, LabDataError)


@pytest.fixture(params=list(READERS))
def reader(request):
    return READERS[request.param][0]


@pytest.fixture
def fifo(short_tmp_path) -> Path:
    path = short_tmp_path / "pipe.csv"  # a short path: the messages show it whole
    os.mkfifo(path)
    return path


def command(capsys, *args: str) -> tuple[int, str, str]:
    """``windpump ARGS`` in this process: its exit code, stdout and stderr."""
    code = cli.main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line(code: int, out: str, err: str, *words: str) -> None:
    """The command line's failure: exit 1 (as every other failure of a command), nothing on
    stdout, one short line on stderr naming the problem, no traceback."""
    assert code == 1 and out == "", (code, out, err)
    assert err.count("\n") == 1 and "Traceback" not in err and len(err) < 400, err
    assert all(word in err for word in words), err


# The guard itself --------------------------------------------------------------------------------


def test_the_guard_reads_bytes_and_paths(tmp_path):
    path = tmp_path / "lab.csv"
    path.write_bytes(LAB)
    assert files.read_bytes(LAB, 100) == LAB
    assert files.read_bytes(bytearray(LAB), 100) == LAB
    assert files.read_bytes(memoryview(LAB), 100) == LAB
    assert files.read_bytes(path, 100) == LAB  # a PathLike
    assert files.read_bytes(str(path), 100) == LAB
    assert files.read_bytes(os.fsencode(path), 100) == os.fsencode(path)  # bytes are contents


def test_the_guard_refuses_a_file_over_its_limit_whatever_it_is(tmp_path):
    path = tmp_path / "big.csv"
    path.write_bytes(b"x" * 101)
    with pytest.raises(LabDataError, match=r"has 101 bytes; at most 100 are read"):
        files.read_bytes(path, 100)
    with pytest.raises(
        LabDataError, match=r"at most 100 are read \(a test curve needs far fewer\)$"
    ):
        files.read_bytes(b"x" * 101, 100, what="a test curve")
    assert files.read_bytes(b"x" * 100, 100) == b"x" * 100


@pytest.mark.timeout(30)
@pytest.mark.parametrize("kind", ["pipe", "folder", "device"])
def test_the_guard_refuses_what_is_not_a_regular_file_without_waiting(tmp_path, fifo, kind):
    path = {"pipe": fifo, "folder": tmp_path, "device": Path("/dev/zero")}[kind]
    with pytest.raises(LabDataError, match=f"is not a regular file but a {kind}") as caught:
        files.read_bytes(path, 100)
    assert "cannot be read" in str(caught.value)


@pytest.mark.parametrize(
    "source, words",
    [
        ("lab\x00.csv", ["source = 'lab\\x00.csv'", "without a NUL byte"]),
        ("/tmp/" + "x" * 10_000, ["source = '/tmp/xxx", "(10,005 characters)", "4,096"]),
        ("time,speed\n0,4\n", ["source = 'time,speed\\n0,4\\n'", "line break", "bytes"]),
        ("x" * 5_000, ["(5,000 characters)", "at most 4,096 characters"]),
        (3.5, ["source = 3.5", "bytes (a file's contents) or a path"]),
        (None, ["source = None"]),
    ],
    ids=["nul", "10k-path", "contents-as-str", "long-str", "float", "none"],
)
def test_the_guard_answers_what_cannot_be_a_path_in_words(source, words):
    with pytest.raises(ParameterError) as caught:
        files.read_bytes(source, 100)
    message = str(caught.value)
    assert len(message) < 300 and all(word in message for word in words), message
    assert "there is no file" not in message  # never looked for on the disk


def test_the_guard_names_the_parameter_it_is_given():
    with pytest.raises(ParameterError, match="^--weather = 'a"):
        files.read_bytes("a\x00b", 100, name="--weather")


def test_a_missing_file_and_one_that_cannot_be_read_are_named(short_tmp_path):
    with pytest.raises(LabDataError, match="there is no file '.*nowhere.csv'"):
        files.read_bytes(short_tmp_path / "nowhere.csv", 100)
    with pytest.raises(LabDataError, match="cannot be read: File name too long"):
        files.read_bytes(short_tmp_path / ("y" * 300), 100)  # a name longer than a folder holds


@given(st.text(max_size=300) | st.text(max_size=5000, alphabet="/ab.\n\x00"))
def test_any_text_is_read_as_a_path_or_refused_by_the_packages_error(text):
    """Never a bare OSError, UnicodeEncodeError (a lone surrogate) or ValueError of another
    kind: the guard's answer is the package's, with a message of bounded length."""
    with tempfile.TemporaryDirectory() as folder:
        before = os.getcwd()
        os.chdir(folder)
        try:
            files.read_bytes(text, 1000)
        except PACKAGE_ERRORS as error:
            assert len(str(error)) < 400
        finally:
            os.chdir(before)


# Each reader goes through it ---------------------------------------------------------------------


def test_every_reader_of_a_users_file_goes_through_the_one_guard(reader, tmp_path, monkeypatch):
    asked = []
    guard = files.read_bytes

    def spy(source, *args, **kwargs):
        asked.append(source)
        return guard(source, *args, **kwargs)

    monkeypatch.setattr(files, "read_bytes", spy)
    path = tmp_path / "file.csv"
    path.write_bytes(next(contents for read, contents in READERS.values() if read is reader))
    reader(path)
    assert [source for source in asked if not isinstance(source, bytes)] == [path]


@pytest.mark.timeout(30)
def test_every_reader_refuses_a_pipe_without_waiting_for_a_writer(reader, fifo):
    with pytest.raises(LabDataError, match="is not a regular file but a pipe"):
        reader(fifo)


def test_every_reader_refuses_a_folder(reader, tmp_path):
    with pytest.raises(LabDataError, match="is not a regular file but a folder"):
        reader(tmp_path)


@pytest.mark.parametrize(
    "path, words",
    [
        ("wind\x00.csv", ["NUL byte"]),
        ("/tmp/" + "w" * 10_000, ["(10,005 characters)", "4,096"]),
    ],
    ids=["nul", "10k-path"],
)
def test_every_reader_answers_a_path_that_cannot_be_one_briefly(reader, path, words):
    with pytest.raises(ParameterError) as caught:
        reader(path)
    message = str(caught.value)
    assert len(message) < 300 and all(word in message for word in words), message
    assert message.startswith(("source = ", "--design = ")), message  # the parameter's name


def test_every_reader_reads_bytes(reader):
    contents = next(contents for read, contents in READERS.values() if read is reader)
    reader(contents)  # (a design file's text is only read here: Design.from_json parses it)


def test_a_weather_files_contents_as_text_are_not_taken_for_a_path():
    """read_weather takes a path or bytes: text holding a line break was looked for as a file
    (``cannot read time,speed...``); it is refused, saying to pass the contents as bytes."""
    with pytest.raises(ParameterError, match="line break.*bytes") as caught:
        read_weather(WIND.decode())
    assert "there is no file" not in str(caught.value)
    assert read_weather(WIND).V.tolist() == [4.0, 5.0, 6.0]


def test_the_csv_readers_still_read_text_holding_a_line_break_as_contents():
    """As documented before the guard: a ``str`` with a line break is the lab and wind files'
    contents, never a path; one without is a path."""
    assert read_torque_csv(LAB.decode()).omega.tolist() == [10.0, 50.0, 90.0]
    assert read_csv(WIND.decode()).V.tolist() == [4.0, 5.0, 6.0]


def test_every_reader_refuses_a_file_over_its_limit(tmp_path, monkeypatch):
    path = tmp_path / "big.csv"
    path.write_bytes(WIND + b"10800,7\n" * 20)
    with pytest.raises(LabDataError, match=r"at most 100 are read"):
        read_csv(path, max_bytes=100)
    with pytest.raises(LabDataError, match=r"at most 100 are read"):
        read_torque_csv(path, max_bytes=100)
    monkeypatch.setattr(windpump.sites.weather, "MAX_CSV_BYTES", 100)
    with pytest.raises(LabDataError, match=r"at most 100 are read"):
        read_weather(path)
    with pytest.raises(LabDataError, match=r"at most 100 are read"):
        read_weather(path.read_bytes())
    monkeypatch.setattr(cliargs, "MAX_FILE_BYTES", 100)  # read_text lives there (issue 38)
    with pytest.raises(LabDataError, match=r"at most 100 are read"):
        cli.read_text(str(path), "--design")


# The command line --------------------------------------------------------------------------------


@pytest.fixture
def weather_command():
    pytest.importorskip("pvlib")
    return ["supply", "--demand", "1", "--weather"]


@pytest.mark.timeout(60)
@pytest.mark.parametrize("option", ["--weather", "--design", "sweep"])
def test_the_command_line_refuses_a_pipe_in_one_line(capsys, fifo, option):
    args = {
        "--weather": ["supply", "--demand", "1", "--weather", str(fifo)],
        "--design": ["simulate", "--design", str(fifo)],
        "sweep": ["sweep", str(fifo)],
    }[option]
    if option == "--weather":
        pytest.importorskip("pvlib")
    code, out, err = command(capsys, *args)
    assert_one_line(code, out, err, "pipe.csv", "is not a regular file but a pipe")


@pytest.mark.parametrize("option", ["--weather", "--design"])
@pytest.mark.parametrize(
    "path, words",
    [
        ("wind\x00.csv", ["NUL byte"]),
        ("/tmp/" + "w" * 10_000, ["(10,005 characters)", "4,096"]),
        ("/", ["is not a regular file but a folder"]),
    ],
    ids=["nul", "10k-path", "folder"],
)
def test_the_command_line_answers_a_bad_path_in_one_short_line(capsys, option, path, words):
    if option == "--weather":
        pytest.importorskip("pvlib")
        args = ["supply", "--demand", "1", "--weather", path]
    else:
        args = ["simulate", "--design", path]
    code, out, err = command(capsys, *args)
    assert_one_line(code, out, err, option, *words)
    assert len(err) < 300, err


@pytest.mark.timeout(120)
def test_windpump_supply_on_a_pipe_exits_with_one_line_not_a_hang(fifo):
    """The probe's own command, in a process of its own: it blocked for ever."""
    pytest.importorskip("pvlib")
    done = subprocess.run(
        [sys.executable, "-m", "windpump", "supply", "--weather", str(fifo), "--demand", "1"],
        capture_output=True,
        text=True,
        timeout=110,
    )
    assert done.returncode == 1 and done.stdout == "", done
    assert done.stderr.count("\n") == 1 and "not a regular file but a pipe" in done.stderr


# A wind CSV near the limit, in bounded memory -----------------------------------------------------

PIECES = [
    "time,speed\n0,4\n3600,5\n7200,6\n",
    "# a mast\r\nt;V\r\n\r\n0;4,5\r\n600;5\r\n# lull\r\n1200;0,5\r\n",
    "0\t4\r600\t5\r1200\t6",  # old Macintosh line ends, no last one
    "2026-01-31T23:00,4\n2026-02-01T00:00,5\n\n2026-02-01 01:00,6\n",
    '"0","4"\n 600 , 5 \n1200,6,\n1800,7\n',  # quotes, spaces, a trailing separator
    "0,4\n600,5\n1200,6\n1800,7\n2400,8\n3000,x\n",  # a bad cell late
    "0,4\n600,5\n1200,6\n1200,7\n",  # a time that repeats
    "0,4\n600,5\n2026-01-01T00:00,6\n",  # seconds, then timestamps
    "0,4\x85600,5\u20281200,6\x0c1800,7\n",  # the rarer line ends str.splitlines knows
]


@pytest.mark.parametrize("text", PIECES)
def test_a_record_read_in_small_pieces_is_the_record_read_whole(text, monkeypatch):
    """A file is parsed ``CHUNK`` characters at a time: pieces of a few characters (each line
    its own piece, a piece ending inside ``\\r\\n``...) read the same samples, months and
    lines, or fail on the same line with the same words, as one piece for the whole file."""

    def outcome():
        try:
            samples = windpump.readers.wind_samples.read_samples(text.encode(), lines=True)
        except LabDataError as error:
            return str(error)
        month = None if samples.month is None else samples.month.tolist()
        return samples.t.tolist(), samples.V.tolist(), samples.line.tolist(), month

    whole = outcome()
    for size in (1, 5, 7, 13):
        monkeypatch.setattr(windpump.readers.wind_samples, "CHUNK", size)
        assert outcome() == whole, size


SECOND = datetime.timedelta(seconds=1)
MEMORY = """
import resource, sys
import windpump, windpump.model.wind, windpump.readers.wind_samples, windpump.sites.weather
reader = {"read_csv": windpump.model.wind.read_csv, "read_weather": windpump.read_weather}[sys.argv[2]]
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
record = reader(sys.argv[1])
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(len(record.t), (after - before) * 1024)
"""


@pytest.mark.timeout(300)
@pytest.mark.parametrize("reader", ["read_csv", "read_weather"])
@pytest.mark.parametrize("times", ["seconds", "iso"])
def test_a_large_wind_csv_is_read_in_memory_a_small_multiple_of_its_size(tmp_path, reader, times):
    """A ~20 MB record (one sample every 3 s) grows the reading process's peak memory by less
    than 10 times the file's size (before: ~36 times, 1.8 GB for 50 MB). Not timed."""
    path = tmp_path / "wind.csv"
    start, count = datetime.datetime(2026, 1, 1), 1_500_000 if times == "seconds" else 800_000
    with open(path, "w", encoding="utf-8") as file:
        file.write("time,speed [m/s]\n")
        for i in range(count):
            moment = 3 * i if times == "seconds" else (start + 3 * SECOND * i).isoformat()
            file.write(f"{moment},{(i * 7919) % 2000 / 100:.2f}\n")
    size = path.stat().st_size
    assert 18e6 < size < 26e6
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(MEMORY), str(path), reader],
        capture_output=True,
        text=True,
        timeout=280,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    samples, grown = map(int, done.stdout.split())
    assert samples == count
    assert grown < 10 * size, f"{grown / 1e6:.0f} MB for a file of {size / 1e6:.0f} MB"
