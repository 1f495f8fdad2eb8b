"""Running the installed ``ufcsr-analyze``: the one place the package starts a program.

The analysis is the analyzer's own program, not a copy of it, so the numbers
are exactly the ones ``ufcsr-analyze`` prints and the package needs no
compiler. This module finds the program, runs it with arguments built from
typed keyword arguments, passes on its progress when asked, turns its
``error:`` lines into :class:`UfcsrError`, and stops it within a second on
Ctrl-C: the program removes its temporaries and exits 130 without touching the
output folder (docs/reliability.md), and KeyboardInterrupt is raised here.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path
from typing import IO, Optional, Sequence

from ._files import UfcsrError

# Where the program is looked for, in order: the argument, these variables, PATH.
PROGRAM = "ufcsr-analyze"
PROGRAM_VARIABLES = ("UFCSR_ANALYZE", "UFCSR_ANALYZE_BIN")
# Seconds the program has to stop after SIGINT before it is killed.
STOP_GRACE_S = 5.0
# The exit codes every ufcsr command shares (docs/guide.md#exit-codes).
EXIT_DONE, EXIT_FAILURES, EXIT_NOTHING_DONE, EXIT_INTERRUPTED = 0, 1, 2, 130


def find_program(executable: Optional[os.PathLike] = None) -> str:
    """The ``ufcsr-analyze`` to run; UfcsrError saying how to get one when there is none."""
    candidates = [os.fspath(executable)] if executable is not None else []
    candidates += [os.environ[name] for name in PROGRAM_VARIABLES if os.environ.get(name)]
    for candidate in candidates:
        if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
        raise UfcsrError(f"{candidate}: not an executable ufcsr-analyze")
    found = shutil.which(PROGRAM)
    if found is None:
        raise UfcsrError(
            f"{PROGRAM} is not on PATH: build it once with `cargo build --release` in the ufcsr repository "
            f"and put target/release on PATH, or set UFCSR_ANALYZE to the program (docs/python.md)"
        )
    return found


def _pump(stream: IO[bytes], lines: list[str], echo: bool) -> None:
    """Collects the program's stderr, echoing it (progress bar and all) when asked, and closes the
    pipe at its end (left open, every call leaked a file: ResourceWarning). The reader closes it, not
    the caller: after Ctrl-C a child of the program may hold the pipe open a while, and the caller
    must not wait for that."""
    with stream:
        for raw in iter(stream.readline, b""):
            text = raw.decode("utf-8", "replace")
            lines.append(text)
            if echo:
                sys.stderr.write(text)
                sys.stderr.flush()


def _stop(process: subprocess.Popen) -> None:
    """SIGINT (the program cleans up and exits 130), then SIGKILL after the grace time."""
    try:
        process.send_signal(signal.SIGINT)
        process.wait(STOP_GRACE_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
    except ProcessLookupError:
        pass


def run(program: str, arguments: Sequence[str], progress: bool) -> int:
    """Runs ``program arguments``; returns 0 or 1, raises UfcsrError or KeyboardInterrupt."""
    process = subprocess.Popen(
        [program, *arguments], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    lines: list[str] = []
    reader = threading.Thread(target=_pump, args=(process.stderr, lines, progress), daemon=True)
    reader.start()
    try:
        # Short waits, so that Ctrl-C reaches this thread within a fraction of a second.
        while True:
            try:
                code = process.wait(0.1)
                break
            except subprocess.TimeoutExpired:
                continue
    except KeyboardInterrupt:
        _stop(process)
        raise
    reader.join()
    if code in (EXIT_DONE, EXIT_FAILURES):
        return code
    errors = [line[len("error: ") :].strip() for line in lines if line.startswith("error: ")]
    if code == EXIT_INTERRUPTED or code == -signal.SIGINT:
        raise KeyboardInterrupt
    message = "; ".join(errors) or "".join(lines[-5:]).strip() or f"exit status {code}"
    raise UfcsrError(f"{Path(program).name} failed: {message}")
