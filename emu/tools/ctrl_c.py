"""Ctrl-C during the encoder check (its hands-off second or its "turn the chuck" question), on a terminal,
against a board's console: the command ends with one line naming it and
exit status 130, and the board's check is stopped (engage is not refused
"an encoder check is running"). For `device check-encoder` and `device
setup`. Run by .ci/emu-device against the real image:

    python3 emu/tools/ctrl_c.py POLYTURN PORT

Exits 1 if a check fails."""

import os
import pty
import select
import signal
import subprocess
import sys
import time


def cancel_at_the_chuck(polyturn, port, command, at=b"Turn the chuck"):
    """Runs `polyturn device --port PORT COMMAND` on a pty, answers the
    setup's first question, and sends SIGINT once `at` is shown ("Turn
    the chuck", or the hands-off second before it)."""
    pid, fd = pty.fork()
    if pid == 0:
        os.execv(polyturn, [polyturn, "device", "--port", port, command])
    out, sent, answered, t0 = b"", False, command != "setup", time.time()
    while time.time() - t0 < 60:
        ready, _, _ = select.select([fd], [], [], 0.5)
        if ready:
            try:
                data = os.read(fd, 4096)
            except OSError:
                break
            if not data:
                break
            out += data
        if not answered and b"index (Z) pulse" in out:
            os.write(fd, b"y")
            answered = True
        if not sent and at in out:
            time.sleep(0.5 if at == b"Turn the chuck" else 0.1)
            os.kill(pid, signal.SIGINT)
            sent = True
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status), out.decode(errors="replace")


def device(polyturn, port, *args):
    r = subprocess.run([polyturn, "device", "--port", port, *args], capture_output=True, text=True, timeout=60)
    return r.returncode, (r.stdout + r.stderr).strip()


def main():
    polyturn, port = sys.argv[1], sys.argv[2]
    failed = False
    for command, at in (("check-encoder", b"Turn the chuck"), ("setup", b"Turn the chuck"), ("check-encoder", b"hands off")):
        code, out = cancel_at_the_chuck(polyturn, port, command, at)
        errors = [l for l in out.splitlines() if "error:" in l]
        want = f"error: {command}: cancelled (Ctrl-C): nothing saved (the board's encoder check stopped)"
        engage = device(polyturn, port, "engage")
        ok = code == 130 and len(errors) == 1 and errors[0].endswith(want) and engage == (0, "ok engaging")
        print(f"  {'ok  ' if ok else 'FAIL'} ctrl-c-{command} at '{at.decode()}': exit {code}, {errors}, then engage: {engage}")
        failed |= not ok
        device(polyturn, port, "stop")
        time.sleep(1)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
