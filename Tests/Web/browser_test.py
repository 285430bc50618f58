#!/usr/bin/python3
"""The live instrument's web page in a real browser (issue 47; docs/ACCESSIBILITY.md "The web page").

  browser_test.py --armadillo BIN --work DIR --case play|read|navigate [--axe-dir DIR]

play:     `armadillo play --simulate --motion M.csv --scene theremin --seconds 14 --no-audio
          --tactile T.csv --web 0`, the page in headless Chromium (Debian's chromium + chromium-driver,
          Selenium): the elevation shown against the motion's held poses (within 3 deg) and changing
          as the arm moves; axe-core (WCAG 2.1 A/AA) without a serious or critical violation; every
          interactive node of Chrome's accessibility tree named; Tab reaching every control; the
          refusals (a foreign Host, a state change from a foreign Origin, GET /../../etc/passwd,
          sent raw); the button named "Panic" stopping every motor (the tactile CSV) from 0.6 s
          after the press, in the session's time the page reports, to the end.
read:     `armadillo read` with a Mosquitto on a free loopback port: the page loads, shows its
          status, and a message published to the topic appears under "Messages read on the arm".
navigate: `armadillo navigate --route R.json --osc-in PORT --simulate --web 0`: the page shows the
          walk (next waypoint, distance) once positions arrive over OSC.
bind:     `play --web 0 --web-bind 127.0.0.1`: the printed address carries the token (and a QR code
          follows); without it every request is refused; with it the page shows the live
          orientation (its files and events through the cookie) and its Panic acts.

Every wait polls with a deadline; the browser, the program and the broker are stopped in finally
blocks. Exit 0 when every check held, 1 with the failures listed otherwise."""
import argparse
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import Select

FAILURES = []


def check(ok, what):
    print(("ok:     " if ok else "FAILED: ") + what, flush=True)
    if not ok:
        FAILURES.append(what)
    return ok


def poll(deadline_s, probe, interval=0.05):
    """probe() until it returns something truthy or the deadline passes (then None)."""
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        value = probe()
        if value:
            return value
        time.sleep(interval)
    return None


def port_open(port):
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1).close()
        return True
    except OSError:
        return False


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# --- the program -------------------------------------------------------------------------------

class Program:
    def __init__(self, args, work, name):
        self.err_path = os.path.join(work, name + ".stderr")
        self.out_path = os.path.join(work, name + ".stdout")
        self.err = open(self.err_path, "w")
        self.out = open(self.out_path, "w")
        print("running: " + " ".join(args), flush=True)
        self.proc = subprocess.Popen(args, cwd=work, stdout=self.out, stderr=self.err, stdin=subprocess.DEVNULL)

    def stderr(self):
        with open(self.err_path, encoding="utf-8", errors="replace") as f:
            return f.read()

    def address(self):
        m = poll(20, lambda: re.search(r"web: (http://\S+)", self.stderr()) or (self.proc.poll() is not None and "exit"))
        if not m or m == "exit":
            raise RuntimeError("no web address on stderr:\n" + self.stderr())
        return m.group(1)

    def wait(self, timeout):
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            if self.wait(10) is None:
                self.proc.kill()
                self.proc.wait()
        self.err.close()
        self.out.close()


def browser(work):
    options = Options()
    options.binary_location = shutil.which("chromium") or "/usr/bin/chromium"
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--disable-dev-shm-usage", "--window-size=1000,1400"):
        options.add_argument(flag)
    options.add_argument("--user-data-dir=" + tempfile.mkdtemp(prefix="chromium-", dir=work))
    service = Service(executable_path=shutil.which("chromedriver") or "/usr/bin/chromedriver")
    return webdriver.Chrome(service=service, options=options)


def text(driver, element_id):
    return driver.execute_script("const e = document.getElementById(arguments[0]); return e ? e.textContent : '';", element_id)


def page_status(driver):
    """(session time s, elevation deg or None) as the page shows them, read together."""
    t, o = driver.execute_script("return [document.getElementById('time').textContent, "
                                 "document.getElementById('orientation').textContent];")
    mt = re.match(r"([0-9.]+) s", t)
    mo = re.search(r"elevation (\u2212?[0-9.]+)\u00b0", o)
    if not mt or not mo:
        return None
    return float(mt.group(1)), float(mo.group(1).replace("\u2212", "-"))


# --- raw HTTP (no client normalises the request) ------------------------------------------------

def raw_request(port, request):
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(request.encode())
        data = b""
        while True:
            try:
                chunk = s.recv(65536)
            except socket.timeout:
                break
            if not chunk:
                break
            data += chunk
            if b"\r\n\r\n" in data:
                head, _, body = data.partition(b"\r\n\r\n")
                m = re.search(rb"Content-Length: (\d+)", head, re.I)
                if m and len(body) >= int(m.group(1)):
                    break
    status = int(data.split(b" ", 2)[1]) if data.startswith(b"HTTP/") else 0
    return status, data.decode(errors="replace")


# --- accessibility ------------------------------------------------------------------------------

def axe_source(axe_dir):
    """axe.min.js from axe_dir (an npm prefix), installed there with npm when absent."""
    path = os.path.join(axe_dir, "node_modules", "axe-core", "axe.min.js")
    if not os.path.exists(path):
        npm = shutil.which("npm")
        if not npm:
            raise RuntimeError("axe-core is not in " + axe_dir + " and npm is not installed")
        subprocess.run([npm, "install", "--prefix", axe_dir, "--no-audit", "--no-fund", "axe-core@4"], check=True, timeout=300)
    with open(path, encoding="utf-8") as f:
        return f.read()


def check_axe(driver, axe_js):
    driver.execute_script(axe_js)
    result = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const tags = ['wcag2a', 'wcag2aa', 'wcag21a', 'wcag21aa'];"
        "axe.run(document, {runOnly: {type: 'tag', values: tags}}).then(function (r) {"
        "  const violations = r.violations.map(v => ({id: v.id, impact: v.impact, nodes: v.nodes.length, help: v.help}));"
        "  done({violations: violations, passes: r.passes.length, version: axe.version});"
        "}).catch(e => done({error: String(e)}));")
    if "error" in result:
        return check(False, "axe-core ran: " + result["error"])
    for v in result["violations"]:
        print(f"        axe {v['impact']}: {v['id']} ({v['nodes']} nodes): {v['help']}")
    bad = [v for v in result["violations"] if v["impact"] in ("serious", "critical")]
    check(not bad, f"axe-core {result['version']} (WCAG 2.1 A/AA): {result['passes']} rules pass, "
                   f"{len(result['violations'])} violations, {len(bad)} serious or critical")


INTERACTIVE = {"button", "link", "textbox", "spinbutton", "combobox", "listbox", "checkbox", "radio", "slider",
               "switch", "tab", "menuitem", "option", "searchbox"}


def check_ax_tree(driver):
    nodes = driver.execute_cdp_cmd("Accessibility.getFullAXTree", {})["nodes"]
    interactive, unnamed = 0, []
    for n in nodes:
        if n.get("ignored"):
            continue
        role = n.get("role", {}).get("value", "")
        if role not in INTERACTIVE:
            continue
        interactive += 1
        name = n.get("name", {}).get("value", "")
        if not str(name).strip():
            unnamed.append(role + " " + str(n.get("nodeId")))
    check(interactive >= 10 and not unnamed,
          f"accessibility tree: {interactive} interactive nodes, unnamed: {unnamed or 'none'}")


def check_tab_order(driver):
    # From a fresh load, so the first Tab starts at the top of the document.
    driver.refresh()
    poll(5, lambda: driver.execute_script("return document.getElementById('param-0') !== null;"))
    keys = driver.execute_script(
        "const all = [...document.querySelectorAll('a[href], button, input, select, textarea, [tabindex]')]"
        "  .filter(e => !e.disabled && e.tabIndex >= 0 && e.getClientRects().length > 0);"
        "all.forEach((e, i) => { if (!e.dataset.tabkey) e.dataset.tabkey = e.id || (e.tagName + i); });"
        "return all.map(e => e.dataset.tabkey);")
    reached = []
    for _ in range(len(keys) + 5):
        webdriver.ActionChains(driver).send_keys(Keys.TAB).perform()
        key = driver.execute_script("const e = document.activeElement; return e && e.dataset ? (e.dataset.tabkey || '') : '';")
        if key and key not in reached:
            reached.append(key)
    missing = [k for k in keys if k not in reached]
    check(len(keys) >= 10 and not missing, f"Tab reaches {len(reached)} of {len(keys)} controls; missed: {missing or 'none'}")
    # The first control after the skip link is the stage's Panic: the stage comes first.
    check(len(reached) > 1 and reached[1] == "panic", f"Tab order begins with the skip link, then Panic: {reached[:3]}")


# --- the play case --------------------------------------------------------------------------------

HOLDS = [(0.0, 3.0, 30.0), (4.0, 7.0, -20.0), (8.0, 20.0, 55.0)]   # (from s, to s, elevation deg)


def write_motion(path):
    rows = ["t,elevation,azimuth,roll"]

    def seg(t0, t1, e0, e1, a0, a1, r0=0.0, r1=0.0):
        n = int(round((t1 - t0) * 100))
        for i in range(n):
            f = i / n
            rows.append(f"{t0 + i * 0.01:.2f},{e0 + (e1 - e0) * f:.3f},{(a0 + (a1 - a0) * f) % 360:.3f},{r0 + (r1 - r0) * f:.3f}")

    seg(0, 3, 30, 30, 0, 0)
    seg(3, 4, 30, -20, 0, 40)
    seg(4, 7, -20, -20, 40, 40)
    seg(7, 8, -20, 55, 40, -30, 0, 20)
    seg(8, 20.01, 55, 55, -30, -30, 20, 20)
    with open(path, "w") as f:
        f.write("\n".join(rows) + "\n")


def held_elevation(t):
    """The motion's elevation at t when the arm has held still for 0.8 s and holds 0.2 s more."""
    for start, end, elevation in HOLDS:
        if start + 0.8 <= t <= end - 0.2:
            return elevation
    return None


def check_orientation(driver):
    """Samples the page until it has shown two different held poses (or the session nears its end)."""
    errors = {}
    seen = set()

    def sample():
        s = page_status(driver)
        if s:
            t, shown = s
            want = held_elevation(t)
            if want is not None:
                errors.setdefault(want, []).append(abs(shown - want))
            seen.add(round(shown))
        return len(errors) >= 2 and all(len(v) >= 5 for v in errors.values())

    poll(11, sample, 0.1)
    for want, errs in sorted(errors.items()):
        check(max(errs) <= 3.0, f"elevation shown while the arm holds {want:+.0f} deg: {len(errs)} samples, "
                                f"worst error {max(errs):.2f} deg (limit 3)")
    check(len(errors) >= 2, f"the page showed {len(errors)} different held poses (need 2: it changes as the arm moves)")
    check(max(seen, default=0) - min(seen, default=0) >= 40, f"the elevation shown spanned {min(seen, default=0)}..{max(seen, default=0)} deg")


def check_refusals(port, token):
    status, _ = raw_request(port, f"GET / HTTP/1.1\r\nHost: evil.example:{port}\r\nConnection: close\r\n\r\n")
    check(status == 403, f"GET / with Host evil.example:{port} refused: HTTP {status}")
    status, _ = raw_request(port, f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n")
    check(status == 200, f"GET / with Host 127.0.0.1:{port} served: HTTP {status}")
    body = "panic"
    status, _ = raw_request(port, f"POST /api/stage HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: http://evil.example\r\n"
                                  f"X-Armadillo-Token: {token}\r\nContent-Type: text/plain\r\nContent-Length: {len(body)}\r\n"
                                  f"Connection: close\r\n\r\n{body}")
    check(status == 403, f"POST /api/stage 'panic' from Origin http://evil.example (with the token) refused: HTTP {status}")
    status, _ = raw_request(port, f"POST /api/stage HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: http://127.0.0.1:{port}\r\n"
                                  f"Content-Type: text/plain\r\nContent-Length: {len(body)}\r\nConnection: close\r\n\r\n{body}")
    check(status == 403, f"POST /api/stage 'panic' from the page's Origin without the token refused: HTTP {status}")
    status, reply = raw_request(port, f"GET /../../etc/passwd HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n")
    check(status in (400, 403, 404) and "root:" not in reply, f"GET /../../etc/passwd (raw) refused: HTTP {status}")
    status, reply = raw_request(port, f"GET /%2e%2e/%2e%2e/etc/passwd HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n")
    check(status in (400, 403, 404) and "root:" not in reply, f"GET /%2e%2e/%2e%2e/etc/passwd (raw) refused: HTTP {status}")


def check_calibration(driver):
    """The page as the third presenter of the device calibration: begin, a step's prompt, skip to the end, the file."""
    driver.find_element(By.XPATH, "//button[normalize-space()='Begin calibration']").click()
    shown = poll(3, lambda: re.match(r"Step 1 of 7: .+", text(driver, "cal-state")))
    check(bool(shown), "calibration: the page shows step 1 of 7: " + text(driver, "cal-state"))
    check(text(driver, "cal-instruction").startswith("What to do: ") and len(text(driver, "cal-instruction")) > 20,
          "calibration: the step's instruction is shown: " + text(driver, "cal-instruction"))
    progress = poll(3, lambda: (m := re.search(r"(\d+)% of its data", text(driver, "cal-state"))) and int(m.group(1)) > 0 and m)
    check(bool(progress), "calibration: the session's raw packets reach the procedure (progress while the arm holds still): " +
          text(driver, "cal-state"))
    for step in range(2, 9):
        driver.find_element(By.XPATH, "//button[normalize-space()='Skip step']").click()
        want = f"Step {step} of 7" if step <= 7 else "complete"
        if not check(bool(poll(3, lambda: want in text(driver, "cal-state"))), f"calibration: after a skip, '{want}': " + text(driver, "cal-state")):
            return
    check("calibration complete" in text(driver, "cal-note"), "calibration: the result is said: " + text(driver, "cal-note"))
    body = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch('api/calibration.json', {credentials: 'same-origin'}).then(r => r.text()).then(done).catch(e => done('error ' + e));")
    check('"accel"' in body and '"gyro"' in body and '"mag"' in body, "calibration: the finished calibration downloads as a calibration file: " + body[:80])


def check_touch(driver):
    """The page as the third presenter of the sensitivity test: begin, a stimulus asked about and
    announced, an answer moves it on, cancel gives the motors back. Returns the first stimulus's
    (motor, level), or None."""
    driver.find_element(By.XPATH, "//button[normalize-space()='Begin the sensitivity test']").click()
    asked = poll(10, lambda: re.search(r"motor m(\d+), level (\d+)", text(driver, "touch-question")))
    if not check(bool(asked), "touch test: the page asks about the first stimulus: " + text(driver, "touch-question") +
                 " / " + text(driver, "touch-state")):
        return None
    first = (int(asked.group(1)), int(asked.group(2)))
    stimuli = int(re.search(r"Stimulus (\d+)", text(driver, "touch-state")).group(1))
    check(bool(poll(3, lambda: asked.group(0) in text(driver, "announce"))), "touch test: the question is announced in the live region")
    driver.find_element(By.XPATH, "//button[normalize-space()='Felt it']").click()
    moved = poll(10, lambda: (m := re.search(r"Stimulus (\d+) .*answer it", text(driver, "touch-state"))) and int(m.group(1)) > stimuli)
    check(bool(moved), "touch test: after Felt it the next stimulus is asked: " + text(driver, "touch-state") + " / " +
          text(driver, "touch-question"))
    driver.find_element(By.XPATH, "//button[normalize-space()='Cancel the test']").click()
    check(bool(poll(3, lambda: "Not running" in text(driver, "touch-state"))), "touch test: cancelled: " + text(driver, "touch-state"))
    check("cancelled" in text(driver, "touch-note"), "touch test: the page says it was cancelled: " + text(driver, "touch-note"))
    return first


def read_tactile(path):
    rows = []
    with open(path) as f:
        header = f.readline().strip().split(",")
        motors = [i for i, name in enumerate(header) if re.fullmatch(r"m\d+", name)]
        for line in f:
            v = line.strip().split(",")
            if len(v) == len(header):
                rows.append((float(v[0]), [float(v[i]) for i in motors]))
    return rows


def check_panic(driver, work):
    button = driver.find_element(By.XPATH, "//button[normalize-space()='Panic']")
    button.click()
    said = poll(5, lambda: re.search(r"Panic sent at session time ([0-9.]+) s", text(driver, "stage-result")))
    if not check(bool(said), "the page says when the panic was taken: " + text(driver, "stage-result")):
        return None
    pressed = float(said.group(1))
    check(bool(poll(3, lambda: "PANIC" in text(driver, "stage-state"))), "the page shows the stage panicked: " + text(driver, "stage-state"))
    check(bool(poll(3, lambda: "Panic" in text(driver, "announce"))), "the panic is announced in the live region")
    return pressed


def check_motors_after(work, pressed):
    rows = read_tactile(os.path.join(work, "T.csv"))
    before = [r for r in rows if pressed - 2.0 <= r[0] < pressed]
    after = [r for r in rows if r[0] >= pressed + 0.6]
    moving_before = sum(1 for _, m in before if any(x > 0 for x in m))
    check(moving_before > 0, f"motors ran before the panic: {moving_before} of {len(before)} rows in the 2 s before t={pressed:.3f}")
    nonzero = [t for t, m in after if any(x > 0 for x in m)]
    last = rows[-1][0] if rows else 0.0
    check(len(after) > 100 and not nonzero,
          f"every motor 0 from t={pressed + 0.6:.3f} s (press + 0.6 s) to the end (t={last:.3f}): {len(after)} rows, "
          f"{len(nonzero)} not all zero" + (f" (first at t={nonzero[0]:.3f})" if nonzero else ""))
    stopped = next((t for t, m in rows if t >= pressed and not any(x > 0 for x in m)), None)
    if stopped is not None:
        print(f"        motors all off at t={stopped:.3f} s, {1000 * (stopped - pressed):.0f} ms after the press was taken")


def run_play(args, work):
    write_motion(os.path.join(work, "M.csv"))
    axe_js = axe_source(args.axe_dir)
    driver, program = None, None
    try:
        started = time.monotonic()
        driver = browser(work)   # started first: the session's 14 s are for the page
        driver.get("about:blank")
        print(f"        Chromium ready in {time.monotonic() - started:.1f} s", flush=True)
        program = Program([args.armadillo, "play", "--simulate", "--motion", "M.csv", "--scene", "theremin", "--seconds", "14",
                           "--no-audio", "--tactile", "T.csv", "--web", "0"], work, "play")
        url = program.address()
        port = int(re.search(r":(\d+)/", url).group(1))
        check(url.startswith("http://127.0.0.1:"), "served on loopback: " + url)
        driver.get(url)
        check(driver.title.startswith("ARMadillo"), "the page loads: " + driver.title)
        check_orientation(driver)
        token = driver.execute_script("return document.querySelector('meta[name=\"armadillo-token\"]').content")
        check_refusals(port, token)
        panics = re.search(r"\((\d+) panic", text(driver, "stage-state"))
        check(panics is None, "the refused panics did not act: " + text(driver, "stage-state"))
        check_axe(driver, axe_js)
        check_ax_tree(driver)
        check_tab_order(driver)
        pressed = check_panic(driver, work)
        check_calibration(driver)   # the arm holds still from t = 8 s: the first step's data comes in
        code = program.wait(30)
        check(code == 0, f"play ended by itself with exit 0: {code}")
        if pressed is not None:
            check_motors_after(work, pressed)
        check("web: panic from 127.0.0.1" in program.stderr(), "stderr names the panic from the page")
    finally:
        if driver:
            driver.quit()
        if program:
            program.stop()


# --- read and navigate ----------------------------------------------------------------------------

def run_read(args, work):
    broker_port = free_port()
    conf = os.path.join(work, "mosquitto.conf")
    with open(conf, "w") as f:
        f.write(f"listener {broker_port} 127.0.0.1\nallow_anonymous true\npersistence false\n")
    broker = subprocess.Popen([shutil.which("mosquitto") or "/usr/sbin/mosquitto", "-c", conf],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    program, driver = None, None
    try:
        check(bool(poll(10, lambda: port_open(broker_port), 0.1)), f"read: Mosquitto listens on 127.0.0.1:{broker_port}")
        driver = browser(work)
        program = Program([args.armadillo, "read", "--simulate", "--mqtt", f"127.0.0.1:{broker_port}", "--messages", "arm/inbox",
                           "--seconds", "30", "--tactile", "T.csv", "--web", "0"], work, "read")
        driver.get(program.address())
        check(bool(poll(10, lambda: "connected" in text(driver, "connected"))), "read: the page shows the status: " + text(driver, "connected"))
        check("braille" in text(driver, "scene"), "read: the scene is braille: " + text(driver, "scene"))

        def published():
            subprocess.run([shutil.which("mosquitto_pub") or "/usr/bin/mosquitto_pub", "-h", "127.0.0.1", "-p", str(broker_port),
                            "-t", "arm/inbox", "-m", "hello"], check=False, timeout=5)
            return poll(2, lambda: "hello" in text(driver, "messages"))

        check(bool(poll(12, published, 0.5)), "read: a message read on the arm is listed: " + text(driver, "messages"))
        check(bool(poll(3, lambda: "Message:" in text(driver, "announce"))), "read: the message is announced")
        stimulus = check_touch(driver)
        code = program.wait(40)
        check(code == 0, f"read ended by itself with exit 0: {code}")
        if stimulus is not None:
            motor, level = stimulus
            alone = [t for t, m in read_tactile(os.path.join(work, "T.csv"))
                     if m[motor - 1] > 0 and all(x == 0 for i, x in enumerate(m) if i != motor - 1)]
            check(len(alone) > 0, f"touch test: motor m{motor} buzzed alone (the stimulus reached the motors): {len(alone)} rows")
    finally:
        if driver:
            driver.quit()
        if program:
            program.stop()
        broker.terminate()
        broker.wait(10)


def osc_message(address, *floats):
    def pad(b):
        return b + b"\0" * (4 - len(b) % 4)
    return pad(address.encode()) + pad(("," + "f" * len(floats)).encode()) + b"".join(struct.pack(">f", x) for x in floats)


def run_navigate(args, work):
    route = os.path.join(work, "R.json")
    with open(route, "w") as f:
        f.write('[{"lat": 52.5200, "lon": 13.4050, "name": "Start"}, {"lat": 52.5210, "lon": 13.4050, "name": "Gate"}]\n')
    osc_port = free_port()
    driver, program = None, None
    try:
        driver = browser(work)
        program = Program([args.armadillo, "navigate", "--route", "R.json", "--osc-in", str(osc_port), "--simulate", "--seconds", "20",
                           "--web", "0"], work, "navigate")
        driver.get(program.address())
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            def shown():
                s.sendto(osc_message("/armadillo/position", 52.5200, 13.4050, 5.0), ("127.0.0.1", osc_port))
                return re.search(r"next waypoint 2 of 2 \(Gate\), (\d+) m away", text(driver, "walk"))
            m = poll(12, shown, 0.2)
        check(bool(m), "navigate: the page shows the next waypoint and its distance: " + text(driver, "walk"))
        if m:
            check(90 <= int(m.group(1)) <= 130, f"navigate: the distance shown ({m.group(1)} m) is the route's 111 m")
        check("simulated forearm" in text(driver, "source"), "navigate: the page shows the status: " + text(driver, "source"))
        check(bool(poll(3, lambda: "walk plays the navigation scene" in text(driver, "scene-result"))),
              "navigate: the page says why the scene cannot be changed: " + text(driver, "scene-result"))
    finally:
        if driver:
            driver.quit()
        if program:
            program.stop()


def run_bind(args, work):
    """--web-bind: the token in the printed address opens the page (cookie), nothing opens it without."""
    driver, program = None, None
    try:
        driver = browser(work)
        program = Program([args.armadillo, "play", "--simulate", "--scene", "theremin", "--seconds", "10", "--no-audio",
                           "--web", "0", "--web-bind", "127.0.0.1"], work, "bind")
        url = program.address()
        m = re.match(r"http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]{32})$", url)
        if not check(bool(m), "bind: the address printed carries the token: " + url):
            return
        port = int(m.group(1))
        check("\u2588" in program.stderr() or "\u2580" in program.stderr(), "bind: a QR code follows the address on stderr")
        for path in ("/", "/app.js", "/api/status", "/events"):
            status, _ = raw_request(port, f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n")
            check(status == 403, f"bind: GET {path} without the token refused: HTTP {status}")
        driver.get(url)
        check(bool(poll(10, lambda: page_status(driver))), "bind: the page opened with the token shows the live orientation: " +
              text(driver, "orientation"))
        # The scene chooser: another scene plays, its parameters follow.
        # The scene list comes from its own request after the first status (app.js loadScene):
        # on a loaded machine the status can be shown before it.
        check(bool(poll(5, lambda: driver.execute_script(
            "return Array.from(document.getElementById('scene-choice').options).some(o => o.value === 'cymbal');"))),
              "bind: the page lists the scenes to choose from")
        Select(driver.find_element(By.ID, "scene-choice")).select_by_visible_text("cymbal")
        driver.find_element(By.XPATH, "//button[normalize-space()='Play this scene']").click()
        check(bool(poll(5, lambda: text(driver, "scene") == "Scene: cymbal.")), "bind: the chosen scene plays: " + text(driver, "scene") +
              " / " + text(driver, "scene-result"))
        check(bool(poll(5, lambda: "cymbal" in text(driver, "params-legend"))), "bind: the cymbal's parameters are shown: " +
              text(driver, "params-legend"))
        driver.find_element(By.XPATH, "//button[normalize-space()='Panic']").click()
        check(bool(poll(5, lambda: "PANIC" in text(driver, "stage-state"))), "bind: Panic from the page acts: " + text(driver, "stage-state"))
    finally:
        if driver:
            driver.quit()
        if program:
            program.stop()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--armadillo", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--case", choices=["play", "read", "navigate", "bind"], required=True)
    ap.add_argument("--axe-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "armadillo", "axe-core"))
    args = ap.parse_args()
    args.armadillo = os.path.abspath(args.armadillo)
    work = os.path.join(os.path.abspath(args.work), args.case)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        {"play": run_play, "read": run_read, "navigate": run_navigate, "bind": run_bind}[args.case](args, work)
    except Exception as e:   # a broken run is a failure, said with its cause
        check(False, f"{type(e).__name__}: {e}")
    if FAILURES:
        print(f"web {args.case}: {len(FAILURES)} check(s) FAILED", flush=True)
        return 1
    print(f"web {args.case}: every check held", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
