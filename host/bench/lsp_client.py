#!/usr/bin/env python3
"""Drives `ger lsp --stdio` as an editor would, for host/bench/lsp.sh: opens
PROGRAM, then edits it as someone typing would: EDITS incremental
didChanges of one line, one every 300 ms, and times how long after the
last one the diagnostics of the edited text are published, while asking
for a hover every 20 ms from the first edit on and timing each answer.

    lsp_client.py GER PROGRAM [EDITS]    (default 10)
"""
import json
import os
import statistics
import subprocess
import sys
import threading
import time


class Server:
    def __init__(self, ger, folder):
        self.process = subprocess.Popen([ger, "lsp", "--stdio"], cwd=folder, stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE)
        self.next_id = 1
        self.lock = threading.Condition()
        self.messages = []
        threading.Thread(target=self.read, daemon=True).start()

    def read(self):
        out = self.process.stdout
        while True:
            length = None
            while True:
                header = out.readline()
                if not header:
                    return
                header = header.strip()
                if not header:
                    break
                if header.startswith(b"Content-Length: "):
                    length = int(header[16:])
            message = json.loads(out.read(length))
            with self.lock:
                self.messages.append((time.perf_counter(), message))
                self.lock.notify_all()

    def send(self, message):
        body = json.dumps(message).encode()
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.process.stdin.flush()

    def notify(self, method, params):
        self.send({"jsonrpc": "2.0", "method": method, "params": params})

    def request(self, method, params):
        id = self.next_id
        self.next_id += 1
        self.send({"jsonrpc": "2.0", "id": id, "method": method, "params": params})
        return id

    def wait(self, wanted, timeout=600):
        """The time and message of the first message `wanted` picks, taken from the list."""
        deadline = time.perf_counter() + timeout
        with self.lock:
            while True:
                for i, (at, message) in enumerate(self.messages):
                    if wanted(message):
                        del self.messages[i]
                        return at, message
                left = deadline - time.perf_counter()
                if left <= 0:
                    sys.exit("no answer in time")
                self.lock.wait(left)


def published(version):
    return lambda m: m.get("method") == "textDocument/publishDiagnostics" and m["params"].get("version") == version


def main():
    ger, program = sys.argv[1], os.path.abspath(sys.argv[2])
    text = open(program).read()
    lines = text.count("\n")
    uri = "file://" + program
    server = Server(ger, os.path.dirname(program))
    asked = server.request("initialize", {"processId": None, "rootUri": None, "capabilities": {}})
    server.wait(lambda m: m.get("id") == asked)
    server.notify("initialized", {})
    start = time.perf_counter()
    server.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "gcode", "version": 1,
                                                            "text": text}})
    at, message = server.wait(published(1))
    print(f"didOpen -> diagnostics ({len(message['params']['diagnostics'])}): {at - start:.2f} s")

    # The edits: lines through the middle of the program each get a comment.
    # Hovers go on from the first until the last one's diagnostics come.
    edits = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    latencies = []
    done = threading.Event()

    def hovers():
        line = 0
        while not done.is_set():
            asked = time.perf_counter()
            id = server.request("textDocument/hover", {"textDocument": {"uri": uri},
                                                       "position": {"line": line, "character": 1}})
            at, _ = server.wait(lambda m: m.get("id") == id)
            latencies.append(at - asked)
            line = (line + 7919) % lines
            time.sleep(0.02)

    asker = threading.Thread(target=hovers)
    for n in range(edits):
        line = lines // 2 + n * 1009
        edit = {"range": {"start": {"line": line, "character": 0}, "end": {"line": line, "character": 0}},
                "text": "(edited) "}
        start = time.perf_counter()
        server.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 2 + n},
                                                 "contentChanges": [edit]})
        if n == 0:
            asker.start()
        if n + 1 < edits:
            time.sleep(0.3)
    at, message = server.wait(published(1 + edits))
    done.set()
    asker.join()
    print(f"{edits} didChanges 300 ms apart, the last -> its diagnostics ({len(message['params']['diagnostics'])}): "
          f"{at - start:.2f} s")
    latencies.sort()
    print(f"hover while editing and analysing: {len(latencies)} hovers, median "
          f"{statistics.median(latencies) * 1000:.1f} ms, 99th percentile "
          f"{latencies[int(len(latencies) * 0.99)] * 1000:.1f} ms, max {latencies[-1] * 1000:.1f} ms")
    asked = server.request("shutdown", None)
    server.wait(lambda m: m.get("id") == asked)
    server.notify("exit", None)
    server.process.wait(timeout=60)


if __name__ == "__main__":
    main()
