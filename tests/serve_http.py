#!/usr/bin/python3
"""softface serve over raw HTTP and WebSocket, without a browser: what it refuses and what a
client that leaves does to it.

Starts `softface serve SCENE` (any free port), then checks, printing each answer:
  GET / and /scene.json: 200; a path outside the web folder: 403; a missing file: 404;
  POST, PUT and DELETE: 405;
  a WebSocket upgrade from another origin, or to another path than /replan: 403;
  clients that send a re-plan and close the connection before the answer (five times), and one
  that closes in the middle of its own frame: the server serves on, and a re-plan then gets its
  binary answer (the id it sent, the moving points' count, 24 + 12 n bytes);
  SIGINT: the server stops, exit code 0.
Exit code 0 when every check holds, 1 otherwise.

usage: serve_http.py SOFTFACE SCENE.prm WORK_DIR
"""
import base64, json, os, re, signal, socket, struct, subprocess, sys, time

softface, scene, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
failures = []


def check(what, value, expected):
    print(f"{what}: {value}")
    if value != expected:
        failures.append(f"{what}: {value}, expected {expected}")


log = open(os.path.join(work, "serve.log"), "w+")
server = subprocess.Popen([softface, "serve", scene], cwd=work, stdout=log,
                          stderr=subprocess.STDOUT)
url = None
for _ in range(1200):
    log.seek(0)
    match = re.search(r"http://([0-9.]+):([0-9]+)/", log.read())
    if match:
        url = match
        break
    if server.poll() is not None:
        break
    time.sleep(0.1)
if url is None:
    log.seek(0)
    print("serve_http: no URL from softface serve:\n" + log.read())
    server.kill()
    sys.exit(1)
host, port = url.group(1), int(url.group(2))


def read_until(s, marker):
    """What the server sends until @p marker has arrived (or it closes)."""
    answer = b""
    while marker not in answer:
        chunk = s.recv(4096)
        if not chunk:
            break
        answer += chunk
    return answer


def request(method, path, headers=None, body=b""):
    """The status of one HTTP/1.1 request."""
    lines = [f"{method} {path} HTTP/1.1", f"Host: {host}:{port}", "Connection: close"]
    lines += [f"{k}: {v}" for k, v in (headers or {}).items()]
    if body:
        lines.append(f"Content-Length: {len(body)}")
    with socket.create_connection((host, port), timeout=30) as s:
        s.sendall(("\r\n".join(lines) + "\r\n\r\n").encode() + body)
        answer = read_until(s, b"\r\n")
    return int(answer.split(b" ")[1]) if answer.startswith(b"HTTP/1.1 ") else answer[:40]


def websocket(path="/replan", origin=None):
    """A socket upgraded to a WebSocket, or the status the server refused it with."""
    key = base64.b64encode(os.urandom(16)).decode()
    headers = [f"GET {path} HTTP/1.1", f"Host: {host}:{port}", "Upgrade: websocket",
               "Connection: Upgrade", f"Sec-WebSocket-Key: {key}", "Sec-WebSocket-Version: 13",
               f"Origin: {origin or f'http://{host}:{port}'}"]
    s = socket.create_connection((host, port), timeout=60)
    s.sendall(("\r\n".join(headers) + "\r\n\r\n").encode())
    answer = read_until(s, b"\r\n\r\n")
    status = int(answer.split(b" ")[1]) if answer.startswith(b"HTTP/1.1 ") else None
    if status != 101:
        s.close()
        return status
    return s


def frame(text):
    """A client's (masked) text frame."""
    payload, mask = text.encode(), os.urandom(4)
    header = bytes([0x81])
    if len(payload) < 126:
        header += bytes([0x80 | len(payload)])
    else:
        header += bytes([0x80 | 126]) + struct.pack(">H", len(payload))
    return header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


def receive(s):
    """(opcode, payload) of the server's next message (its fragments joined)."""
    def exactly(n):
        data = b""
        while len(data) < n:
            chunk = s.recv(n - len(data))
            if not chunk:
                raise ConnectionError("closed")
            data += chunk
        return data
    opcode, payload, final = None, b"", False
    while not final:
        first, second = exactly(2)
        final, opcode = first & 0x80, opcode or first & 0x0F
        length = second & 0x7F
        if length == 126:
            length = struct.unpack(">H", exactly(2))[0]
        elif length == 127:
            length = struct.unpack(">Q", exactly(8))[0]
        payload += exactly(length)
    return opcode, payload


plan = {"id": 7, "model": "mass tensor", "motions": {"bone": [0, 0, 6, 0, 0, 0]}}
try:
    check("GET /", request("GET", "/"), 200)
    check("GET /scene.json", request("GET", "/scene.json"), 200)
    check("GET /nothing", request("GET", "/nothing"), 404)
    check("GET /three/addons/../x", request("GET", "/three/addons/../x"), 403)
    for method in ("POST", "PUT", "DELETE"):
        check(f"{method} /scene.json", request(method, "/scene.json", body=b"{}"), 405)
    check("WebSocket from another origin", websocket(origin="http://elsewhere.example"), 403)
    check("WebSocket to /scene.json", websocket("/scene.json"), 403)

    for _ in range(5):
        s = websocket()
        s.sendall(frame(json.dumps(plan)))
        s.close()
    s = websocket()
    s.sendall(frame(json.dumps(plan))[:7])
    s.close()
    check("GET /scene.json after clients left", request("GET", "/scene.json"), 200)

    s = websocket()
    check("WebSocket to /replan", isinstance(s, socket.socket), True)
    plan["id"] = 11
    s.sendall(frame(json.dumps(plan)))
    opcode, answer = receive(s)
    s.close()
    check("re-plan answer is binary", opcode, 2)
    answer_id, = struct.unpack("<I", answer[:4])
    n, = struct.unpack("<I", answer[16:20])
    check("re-plan answer id", answer_id, 11)
    check("re-plan answer bytes - 12 n", len(answer) - 12 * n, 24)
    print(f"moving points: {n}")
except (OSError, ConnectionError) as e:
    failures.append(f"connection: {e}")

server.send_signal(signal.SIGINT)
try:
    code = server.wait(timeout=60)
except subprocess.TimeoutExpired:
    server.kill()
    code = "none (killed after 60 s)"
check("exit code after SIGINT", code, 0)
log.seek(0)
if failures:
    print("serve_http: failed:\n  " + "\n  ".join(failures) + "\n--- serve.log:\n" + log.read())
    sys.exit(1)
