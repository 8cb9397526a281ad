"""The body of one Ray task: run `mtwin dataset … --shard I/S` (standard library only).

The driver registers this module for pickling by value, so a Ray worker needs only Python and
Ray, not this package: nothing here may import from ``mtwin_ray``.
"""

from __future__ import annotations

import hashlib
import os
import socket
import subprocess
import tempfile
import time
from typing import Dict, List, Optional, Sequence

#: How much of the process's stderr goes into the exception (Ray shows it).
STDERR_TAIL = 8000


class ShardFailed(RuntimeError):
    """`mtwin dataset` exited non-zero (or could not be started) for one shard."""


def _tail(text: str, limit: int = STDERR_TAIL) -> str:
    text = text.strip()
    return text if len(text) <= limit else "…" + text[-limit:]


def materialise(binary: bytes, digest: str) -> str:
    """Writes a shipped binary once per node (by content) and returns its path."""
    path = os.path.join(tempfile.gettempdir(), f"mtwin-{digest[:16]}")
    if os.path.isfile(path) and os.access(path, os.X_OK):
        return path
    if hashlib.sha256(binary).hexdigest() != digest:
        raise ShardFailed("the shipped mtwin binary arrived damaged (sha256 differs)")
    fd, tmp = tempfile.mkstemp(prefix=".mtwin-", dir=os.path.dirname(path))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(binary)
        os.chmod(tmp, 0o755)
        os.replace(tmp, path)  # atomic: tasks on the same node may race here
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def run_shard(
    argv: Sequence[str],
    shard: int,
    env: Optional[Dict[str, str]] = None,
    binary: Optional[bytes] = None,
    digest: Optional[str] = None,
) -> Dict:
    """Runs ``argv`` (the full `mtwin dataset … --shard I/S` command) and waits for it.

    Returns what the driver logs: shard, host, seconds, and the tail of stderr. Raises
    :class:`ShardFailed` with the command, exit code and stderr when the process fails, so that
    Ray shows the reason and (``retry_exceptions=True``) runs the task again. With ``binary``
    (the bytes of a shipped mtwin, ``digest`` its sha256), ``argv[0]`` is replaced by a copy
    written once per node.
    """
    argv: List[str] = [str(a) for a in argv]
    if binary is not None:
        argv[0] = materialise(binary, str(digest))
    host = socket.gethostname()
    full_env = None
    if env:
        full_env = dict(os.environ)
        full_env.update(env)
    start = time.monotonic()
    try:
        proc = subprocess.run(
            argv,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env=full_env,
            check=False,
        )
    except OSError as e:  # binary missing, not executable, wrong architecture
        raise ShardFailed(
            f"shard {shard}: cannot start {argv[0]!r} on {host} (cwd {os.getcwd()}): {e}"
        ) from None
    seconds = time.monotonic() - start
    stderr = proc.stderr.decode("utf-8", "replace")
    if proc.returncode != 0:
        # check=True semantics, with the reason in the message rather than in a
        # CalledProcessError whose str() drops stderr.
        raise ShardFailed(
            f"shard {shard} failed on {host} after {seconds:.1f} s:"
            f" exit code {proc.returncode} from\n  {subprocess.list2cmdline(argv)}\n"
            f"stderr:\n{_tail(stderr) or '(empty)'}"
        )
    return {
        "shard": shard,
        "host": host,
        "pid": os.getpid(),
        "seconds": seconds,
        "stdout": _tail(proc.stdout.decode("utf-8", "replace"), 2000),
        "stderr": _tail(stderr, 2000),
    }
