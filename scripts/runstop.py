"""runstop.py - stop a run of the benchmark and sweep scripts whole (stability_sweep.py, bench_speedups.py):
a run started with subprocess.Popen(..., start_new_session=True), with everything it started."""
import os
import signal
import time


def session_pids(sid):
    """the live processes of session sid: a run started in a session of its own, with everything it
    started (mpiexec gives its ranks process groups of their own, in the same session)"""
    pids = []
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as f:
                st = f.read()
        except OSError:
            continue
        fields = st[st.rindex(")") + 2:].split()  # state, ppid, pgrp, session, ...
        if fields[0] != "Z" and int(fields[3]) == sid:
            pids.append(int(d))
    return pids


def stop_run(p, grace=10.0):
    """stop a run started with start_new_session=True, and all it started: SIGTERM to its process
    group (timeout and mpiexec, which stops its ranks), then SIGKILL to whatever of its session is
    left after grace seconds. (Killing timeout alone, SIGKILL, passed nothing on: mpiexec and the
    ranks ran on, orphans.)"""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(p.pid, sig)
        except OSError:
            pass
        if sig == signal.SIGKILL:
            for pid in session_pids(p.pid):
                try:
                    os.kill(pid, sig)
                except OSError:
                    pass
        deadline = time.time() + grace
        while time.time() < deadline:
            p.poll()
            if p.returncode is not None and not session_pids(p.pid):
                return
            time.sleep(0.1)
    p.wait()
