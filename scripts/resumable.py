"""Commands of a long experiment that a rerun skips where they are up to date (make's rule), so that
`make displacement` (hours on 2 cores) goes on where an interrupted run stopped.

A command that ran to the end leaves a record beside its first output, OUTPUT.command.json: its
command line and what the caller asks to keep (a render's seconds). A rerun skips the command while
that record holds the same command line, every output exists, and no input (the tool itself, the
files it reads) is newer than the oldest output. A command that stopped halfway leaves no record
(the record is removed before it starts), so it runs again.
"""

import json
import os
import pathlib
import subprocess
import time


def record_path(output):
    return pathlib.Path(str(output) + ".command.json")


def _line(command):
    return [str(c) for c in command]


def up_to_date(command, outputs, inputs):
    """The record of `command` if it made `outputs` from these `inputs` and none changed since; else None."""
    try:
        record = json.loads(record_path(outputs[0]).read_text())
        oldest = min(os.stat(o).st_mtime_ns for o in outputs)
        newest = max((os.stat(i).st_mtime_ns for i in inputs), default=0)
    except (OSError, ValueError):
        return None
    if record.get("command") != _line(command) or newest > oldest:
        return None
    return record


def run_resumable(command, outputs, inputs, resume, run=None):
    """Runs `command` unless `resume` and it is up to date; returns (its stdout or None when skipped,
    its record). `run(command)` runs it (default: subprocess, failing on a non-zero exit); the record
    gains the seconds the command took."""
    if resume:
        record = up_to_date(command, outputs, inputs)
        if record is not None:
            return None, record
    record_path(outputs[0]).unlink(missing_ok=True)
    start = time.time()
    stdout = (run or run_command)(command)
    record = {"command": _line(command), "seconds": time.time() - start}
    record_path(outputs[0]).write_text(json.dumps(record) + "\n")
    return stdout, record


def write_if_changed(path, text):
    """Writes `text` to `path` unless it holds it already (keeping its time for up_to_date)."""
    path = pathlib.Path(path)
    if not (path.exists() and path.read_text() == text):
        path.write_text(text)


def run_command(command):
    """Runs a command line (any items, as strings), failing on a non-zero exit; its stdout."""
    return subprocess.run(_line(command), check=True, capture_output=True, text=True).stdout
