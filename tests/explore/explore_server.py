"""Starts `mrr explore` on a free port for a test and stops it (shared by the API and browser tests)."""
import json
import os
import re
import subprocess
import threading
import time
import urllib.error
import urllib.request


class ExploreServer:
    """`mrr explore --port 0 ...` in the background; `url` once it serves."""

    def __init__(self, mrr, *args):
        self.proc = subprocess.Popen([mrr, "explore", "--port", "0", *args], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, text=True)
        self.stderr_lines = []
        self.url = None
        ready = threading.Event()

        def read():
            for line in self.proc.stderr:
                self.stderr_lines.append(line)
                m = re.match(r"mrr explore: serving (http://[0-9.]+:[0-9]+/)", line)
                if m:
                    self.url = m.group(1)
                    ready.set()
            ready.set()

        threading.Thread(target=read, daemon=True).start()
        ready.wait(60)
        if not self.url:
            self.stop()
            raise RuntimeError("mrr explore did not start: " + "".join(self.stderr_lines))

    def get(self, path, timeout=120):
        """(status, content type, body bytes) of GET url+path; 4xx/5xx are returned, not raised."""
        try:
            with urllib.request.urlopen(self.url + path, timeout=timeout) as r:
                return r.status, r.headers.get("Content-Type", ""), r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.headers.get("Content-Type", ""), e.read()

    def json(self, path, timeout=120):
        status, ctype, body = self.get(path, timeout)
        return status, json.loads(body.decode())

    def alive(self):
        return self.proc.poll() is None

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


def port_required():
    return os.environ.get("MRR_REQUIRE_GL") == "1"
