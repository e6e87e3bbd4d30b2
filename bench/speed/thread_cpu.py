"""Run a Python script as __main__ and write each of its threads' CPU seconds.

    thread_cpu.py OUT.json SCRIPT [ARGS...]

A daemon thread reads /proc/self/task/*/stat every PERIOD s (and once at
exit), keeping each thread's last reading, so threads that end early
count too (up to PERIOD s of their CPU may be missed). Threads are named
by their name and target function (threading.Thread; rospy names a
subscriber's by its topic) or, for threads started with _thread (rospy's
XML-RPC server), as such once Python has seen them, else "other". The sampler's own thread is
reported as such. bench/speed/course_profile.py uses it beside py-spy: exact
CPU per thread, where py-spy's samples give where in a thread.
"""
import json
import os
import runpy
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common import stat_cpu  # noqa: E402

PERIOD = 0.2


def _cpu(tid):
    return stat_cpu('/proc/self/task/%d/stat' % tid)


def _name(thread):
    if thread is threading.main_thread():
        return 'main thread'
    target = getattr(thread, '_target', None)
    if target is not None:  # rospy names a subscriber's thread by its topic
        return '%s: %s.%s' % (thread.name, getattr(target, '__module__', '?'),
                              getattr(target, '__qualname__', repr(target)))
    if isinstance(thread, threading._DummyThread):
        return 'a _thread thread (rospy\'s XML-RPC server)'
    return '%s.%s' % (type(thread).__module__, type(thread).__qualname__)


class Sampler(object):

    def __init__(self):
        self.last = {}  # tid: [name, cpu]
        self.lock = threading.Lock()
        self.thread = threading.Thread(target=self._run, name='thread_cpu', daemon=True)
        self.thread.start()

    def sample(self):
        names = {t.native_id: _name(t) for t in threading.enumerate()
                 if getattr(t, 'native_id', None)}
        names[self.thread.native_id] = 'thread_cpu sampler (bench)'
        with self.lock:
            for entry in os.listdir('/proc/self/task'):
                tid = int(entry)
                cpu = _cpu(tid)
                if cpu is None:
                    continue
                name = names.get(tid) or (self.last.get(tid) or ['other'])[0]
                self.last[tid] = [name, cpu]

    def _run(self):
        while True:
            self.sample()
            time.sleep(PERIOD)

    def totals(self):
        self.sample()
        out = {}
        with self.lock:
            for name, cpu in self.last.values():
                out[name] = out.get(name, 0.0) + cpu
        return out


def main():
    out, script = sys.argv[1], sys.argv[2]
    sys.argv = sys.argv[2:]
    sampler = Sampler()
    try:
        runpy.run_path(script, run_name='__main__')
    finally:
        with open(out, 'w') as f:
            json.dump(sampler.totals(), f, indent=1, sort_keys=True)


if __name__ == '__main__':
    main()
