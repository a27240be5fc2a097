"""A run killed with SIGKILL while writing checkpoints always leaves a newest
checkpoint that restarts; a checkpoint from another input is refused (exit 2).

Usage: /usr/bin/python3 check_kill.py MPMICE PROBLEM.yaml OTHER_PROBLEM.yaml WORK_DIR
PROBLEM runs with a checkpoint after every step and is killed at 6 random moments;
after each kill `--restart latest` must run two more steps and exit 0, within a
time limit. Then OTHER (a different grid) restarted from PROBLEM's checkpoint must
exit 2 naming the grid.

Before each restart the test also leaves, taken, the POSIX semaphore that Open MPI's
`sm` shared-file-pointer component would have left had the kill come while it held
it, named after the checkpoint the restart writes first: with that component in use
the restart would wait on it forever (found as an occasional hang of this test)."""
import _multiprocessing
import os
import random
import shutil
import signal
import subprocess
import sys
import time


def main():
    exe, problem, other, work = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    common = [problem, "--no-progress", "--output-dir", work, "--set", "checkpoint.interval=1",
              "--set", "checkpoint.keep=2"]
    rng = random.Random(7)
    for trial in range(6):
        first = trial == 0
        cmd = [exe] + common + ([] if first else ["--restart", "latest"])
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if first:  # a slow (e.g. sanitized) build may need long to write its first checkpoint
            deadline = time.time() + 120
            while time.time() < deadline and proc.poll() is None and not any(
                    f.startswith("checkpoint_") and f.endswith(".h5") for f in os.listdir(work)):
                time.sleep(0.05)
        time.sleep(rng.uniform(0.2, 1.0))
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        ckpts = sorted(f for f in os.listdir(work) if f.startswith("checkpoint_") and f.endswith(".h5"))
        if not ckpts:
            sys.exit("FAIL: no complete checkpoint after kill %d" % trial)
        step = int(ckpts[-1][len("checkpoint_"):-3])
        semaphore = "/OMPIO_checkpoint_%06d.h5.tmp" % (step + 1)  # Open MPI 4.1's name for it
        try:
            _multiprocessing.SemLock(1, 0, 1, semaphore, False)  # a semaphore, value 0 (taken), kept
        except FileExistsError:
            pass  # left by an earlier kill
        try:
            r = subprocess.run([exe] + common + ["--restart", "latest", "--max-steps", str(step + 2)],
                               capture_output=True, text=True, timeout=300)
        except subprocess.TimeoutExpired:
            sys.exit("FAIL: restart from %s after kill %d still running after 300 s" % (ckpts[-1], trial))
        finally:
            _multiprocessing.sem_unlink(semaphore)
        if r.returncode != 0:
            sys.exit("FAIL: restart from %s after kill %d exited %d:\n%s" % (ckpts[-1], trial, r.returncode, r.stderr))
        print("kill %d: restarted from %s" % (trial, ckpts[-1]))
    latest = sorted(f for f in os.listdir(work) if f.startswith("checkpoint_") and f.endswith(".h5"))[-1]
    r = subprocess.run([exe, other, "--no-progress", "--output-dir", os.path.join(work, "other"),
                        "--restart", os.path.join(work, latest)], capture_output=True, text=True)
    if r.returncode != 2 or "another grid" not in r.stderr:
        sys.exit("FAIL: an incompatible checkpoint gave exit %d: %s" % (r.returncode, r.stderr))
    print("incompatible checkpoint refused: " + r.stderr.strip().splitlines()[-1])
    print("kill test passed")


if __name__ == "__main__":
    main()
