"""Ctrl-C is one line at every moment of a command: while it loads, inside callbacks, at the end.

Each case is made deterministic: the SIGINT is raised at the very point (an import hook, a
weakref callback, an atexit handler that holds the teardown open), in a new process.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

#: run the console script's main() with argv; HOOK is placed before it
CONSOLE = """
import sys
{hook}
sys.argv = ["scara-opt", *{argv!r}]
from scara_opt.cli.console import main
main()
"""


def _run(code: str, **kw) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=env, timeout=300, **kw)


def test_ctrl_c_while_the_command_line_loads_is_one_line():
    """A SIGINT while scara_opt.cli.app is being imported (numpy, pandas...: the first tenths of
    a second after start) gave an 11-33-line traceback; now ``scara-opt: interrupted``, 130.

    Mutation caught: console.main importing the CLI outside its try -> traceback; fails.
    """
    hook = """
import signal
class Hook:  # Ctrl-C at the moment the command line's modules start loading
    def find_spec(self, name, path, target=None):
        if name == "scara_opt.cli.app":
            signal.raise_signal(signal.SIGINT)
sys.meta_path.insert(0, Hook())
"""
    run = _run(CONSOLE.format(hook=hook, argv=["robots"]))
    assert run.returncode == 130, run.stderr
    assert run.stderr == "scara-opt: interrupted\n" and run.stdout == ""


def test_ctrl_c_during_the_teardown_after_a_command_changes_nothing():
    """A SIGINT after the command finished (Python's teardown: threads joined, atexit
    handlers, the collector) killed the process by SIGINT with no message, or printed a
    traceback; now the process ends as soon as the command does, with its exit code.

    An atexit handler that sleeps 20 s holds the teardown open, as a slow one would.
    Mutation caught: ``exit_now`` replaced by ``sys.exit(code)`` -> the handler runs, the
    SIGINT lands in it ("Exception ignored in atexit callback"), and the run takes 20 s;
    fails.
    """
    hook = "import atexit, time\natexit.register(time.sleep, 20)"
    code = CONSOLE.format(hook=hook, argv=["fk", "zavar2024", "0", "0", "0", "0"])
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    lines = [proc.stdout.readline(), proc.stdout.readline()]  # the command's whole output
    for _ in range(50):  # Ctrl-C as the process ends, until it has
        if proc.poll() is not None:
            break
        proc.send_signal(signal.SIGINT)
        time.sleep(0.02)
    _, err = proc.communicate(timeout=60)
    assert lines[0].startswith("zavar2024: tip at") and "orientation" in lines[1]
    # 130 and its one line only if the Ctrl-C beat main()'s last few steps
    assert (proc.returncode, err) in ((0, ""), (130, "scara-opt: interrupted\n")), err
    assert time.perf_counter() - start < 15


#: a SIGINT inside a callback Python calls from C and whose exceptions it drops: a function
#: named as weakref's own (WeakKeyDictionary's ``remove``), or a ``__del__``
CALLBACK = """
import signal, sys, time, weakref
from scara_opt import interrupt
ns = {{}}
exec(compile("import signal\\ndef remove(ref):\\n    signal.raise_signal(signal.SIGINT)\\n"
             "    total = 0\\n    for i in range(1000):\\n        total += i\\n",
             "{filename}", "exec"), ns)
class Key:
    def __del__(self):
        if {in_del}:
            ns["remove"](None)
try:
    with interrupt.watch():
        key = Key()
        ref = weakref.ref(key, None if {in_del} else ns["remove"])
        del key          # the collector runs the callback: Ctrl-C lands inside it
        time.sleep(1.0)  # main-line code: the interrupt must reach it
    print("not interrupted")
except KeyboardInterrupt:
    print("interrupted")
"""


def test_ctrl_c_inside_a_weakref_callback_or_finalizer_reaches_the_command():
    """A SIGINT that lands in WeakKeyDictionary's callback (or a ``__del__``) printed
    "Exception ignored in: <function WeakKeyDictionary.__init__.<locals>.remove>" with a
    traceback through interrupt.py, and the interrupt was lost; now nothing is printed and
    the KeyboardInterrupt reaches the main-line code.

    Mutation caught: ``_note_sigint`` raising wherever it lands (as before) -> "Exception
    ignored" on stderr and "not interrupted"; fails.
    """
    for filename, in_del in (("/usr/lib/python3/weakref.py", False), ("mine.py", True)):
        run = _run(CALLBACK.format(filename=filename, in_del=in_del))
        assert (run.stdout, run.stderr) == ("interrupted\n", ""), (filename, run.stderr)
