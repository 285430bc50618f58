#!/usr/bin/env python3
"""Pure Data's [armadillo] and [armadillo~] tested in a real Pd (issue 46; docs/PUREDATA.md).

  pd_objects_test.py CASE --pd PD --externals DIR --patches DIR --armadillo CLI --work DIR

Runs Debian's `pd -nogui -nosound -stderr` (real time: the sources run on their own threads) on
the test patches in Tests/Pd/patches, driven by -send, and reads what they print on stderr. Every
duration is Pd's logical time (a [delay] before `pd quit`), never a sleep of this script. CASE:

  theremin   [armadillo~] with `simulate MOTION.csv` and `scene theremin`: the orientation inside
             each held pose of the motion within 3 degrees, and the signal outlet's pitch there
             within 10 cents of `armadillo render --scene theremin --motion MOTION.csv`.
  motors     [armadillo] in scene patch given `motors 15 0 0 0 8 0 0 0 3` reports, within a
             second, motors 1, 5 and 9 on, m1 >= m5 >= m9, every other motor 0.
  help       every help patch and example opens with no "couldn't create" and no error.
  errors     bad messages (an unknown scene, a port that does not open, a wrong count of motor
             levels, a missing file, ...) are answered with a Pd error naming the problem, and
             both objects keep working.
Exit 0 when every check holds; 1 with what failed."""
import argparse
import glob
import math
import os
import struct
import subprocess
import sys

import numpy as np

# The motion: five held poses (elevation, azimuth, roll in degrees), HOLD s each, MOVE s between.
POSES = [(0.0, 0.0, 0.0), (30.0, 20.0, 0.0), (-20.0, -30.0, 10.0), (45.0, 10.0, -20.0), (10.0, 40.0, 0.0)]
HOLD, MOVE, RATE = 2.0, 0.5, 100


def fail(msg):
    print("FAIL: " + msg)
    return 1


def run_pd(args, patch, sends, extra_open=()):
    cmd = [args.pd, "-nogui", "-nosound", "-stderr", "-r", "48000", "-path", args.externals, "-open", patch]
    for p in extra_open:
        cmd += ["-open", p]
    if sends:
        cmd += ["-send", "; ".join(sends)]
    print("$ " + " ".join(cmd))
    # The patch quits itself ([delay] in logical time); the timeout only keeps a hung Pd from
    # hanging the suite, and fails the case.
    env = dict(os.environ)
    if args.preload:   # a sanitizer build: its runtime first, Pd's own leaks at exit not reported
        env["LD_PRELOAD"] = " ".join(args.preload)
        env["ASAN_OPTIONS"] = env.get("ASAN_OPTIONS", "") + ":detect_leaks=0"
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env)
    except subprocess.TimeoutExpired as e:
        text = (e.stdout or b"").decode(errors="replace") + (e.stderr or b"").decode(errors="replace")
        return -1, text.splitlines() + ["error: Pd did not quit within 120 s (the patch's [delay] never fired)"]
    out = r.stdout + r.stderr
    return r.returncode, out.splitlines()


def write_motion(path):
    rows, t = [], 0.0
    for i, p in enumerate(POSES):
        for _ in range(int(HOLD * RATE)):
            rows.append((t,) + p)
            t += 1.0 / RATE
        if i + 1 < len(POSES):
            q = POSES[i + 1]
            n = int(MOVE * RATE)
            for k in range(n):
                rows.append((t,) + tuple(a + (b - a) * k / n for a, b in zip(p, q)))
                t += 1.0 / RATE
    with open(path, "w") as f:
        f.write("t,elevation,azimuth,roll\n")
        for r in rows:
            f.write("%.3f,%.3f,%.3f,%.3f\n" % r)
    return t


def hold_window(i, margin_start=0.5, margin_end=0.2):
    start = i * (HOLD + MOVE)
    return start + margin_start, start + HOLD - margin_end


def read_wav(path):
    """Mono float samples and the rate of a PCM or float WAV (plain or extensible)."""
    d = open(path, "rb").read()
    if d[:4] != b"RIFF" or d[8:12] != b"WAVE":
        raise ValueError(path + " is not a WAV file")
    i, tag, ch, sr, bits, raw = 12, None, 1, 0, 16, b""
    while i + 8 <= len(d):
        cid, size = d[i:i + 4], struct.unpack("<I", d[i + 4:i + 8])[0]
        body = d[i + 8:i + 8 + size]
        if cid == b"fmt ":
            tag, ch, sr, _, _, bits = struct.unpack("<HHIIHH", body[:16])
            if tag == 0xFFFE:
                tag = struct.unpack("<H", body[24:26])[0]
        elif cid == b"data":
            raw = body
        i += 8 + size + (size & 1)
    if tag == 3:
        x = np.frombuffer(raw, dtype="<f4" if bits == 32 else "<f8").astype(float)
    elif tag == 1 and bits == 16:
        x = np.frombuffer(raw, dtype="<i2").astype(float) / 32768.0
    elif tag == 1 and bits == 24:
        b = np.frombuffer(raw[:len(raw) // 3 * 3], dtype=np.uint8).reshape(-1, 3).astype(np.int32)
        v = b[:, 0] | (b[:, 1] << 8) | (b[:, 2] << 16)
        x = np.where(v >= 1 << 23, v - (1 << 24), v).astype(float) / (1 << 23)
    elif tag == 1 and bits == 32:
        x = np.frombuffer(raw, dtype="<i4").astype(float) / 2.0 ** 31
    else:
        raise ValueError("%s: WAV format %s/%s bits not read here" % (path, tag, bits))
    x = x[:len(x) // ch * ch].reshape(-1, ch).mean(axis=1)
    return x, sr


def pitch_hz(x, sr, lo=40.0, hi=2500.0):
    """The fundamental by autocorrelation (the first peak within 90 % of the highest), refined
    by a parabola through the peak; None for silence."""
    x = x - x.mean()
    if len(x) < sr * 0.05 or np.sqrt(np.mean(x * x)) < 1e-4:
        return None
    n = len(x)
    spec = np.fft.rfft(x * np.hanning(n), 2 * n)
    ac = np.fft.irfft(np.abs(spec) ** 2)[:n]
    a, b = int(sr / hi), int(sr / lo)
    seg = ac[a:b]
    best = seg.max()
    peaks = [k for k in range(1, len(seg) - 1) if seg[k] >= seg[k - 1] and seg[k] >= seg[k + 1] and seg[k] >= 0.9 * best]
    k = a + (peaks[0] if peaks else int(np.argmax(seg)))
    y0, y1, y2 = ac[k - 1], ac[k], ac[k + 1]
    den = y0 - 2 * y1 + y2
    d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
    return sr / (k + d)


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def pose_quaternion(el, az, roll):
    """docs/INTERFACES.md "Frames and poses": q = qY(90 - azimuth) qz(elevation) qx(roll)."""
    def axis(a, deg):
        h = math.radians(deg) / 2
        v = [0.0, 0.0, 0.0]
        v[a] = math.sin(h)
        return (math.cos(h), v[0], v[1], v[2])
    return qmul(qmul(axis(1, 90.0 - az), axis(2, el)), axis(0, roll))


def angle_deg(a, b):
    """The smallest difference of two angles in degrees."""
    return abs((a - b + 180.0) % 360.0 - 180.0)


def case_theremin(args):
    motion = os.path.join(args.work, "held-poses.csv")
    length = write_motion(motion)
    ref = os.path.join(args.work, "theremin-render.wav")
    rec = os.path.join(args.work, "theremin-pd.wav")
    for p in (ref, rec):
        if os.path.exists(p):
            os.remove(p)
    r = subprocess.run([args.armadillo, "render", "--scene", "theremin", "--motion", motion, "--out", ref],
                       capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        return fail("armadillo render: " + r.stderr)
    end_ms = int((length + 0.5) * 1000)
    code, lines = run_pd(args, os.path.join(args.patches, "tilde_theremin.pd"),
                         ["pd dsp 1", "rec open " + rec, "rec start", "cmd scene theremin", "cmd simulate " + motion,
                          "end %d" % end_ms])
    errors = [l for l in lines if "error" in l.lower() or "couldn't create" in l]
    if errors:
        return fail("Pd said:\n  " + "\n  ".join(errors))
    reports, quat, mismatch, pairs = [], None, 0.0, 0
    for l in lines:
        if l.startswith("quat:"):
            quat = [float(s) for s in l.split()[1:]]
        if l.startswith("orient:"):
            v = [float(s) for s in l.split()[1:]]
            if len(v) == 4:
                reports.append(v)
                if quat is not None and len(quat) == 4:   # the same step's `quaternion`, sent just before
                    q = pose_quaternion(v[1], v[2], v[3])
                    d = min(max(abs(a - b) for a, b in zip(q, quat)), max(abs(a + b) for a, b in zip(q, quat)))
                    mismatch, pairs = max(mismatch, d), pairs + 1
                quat = None
    print("quaternion vs orientation: %d pairs, largest component difference %.5f" % (pairs, mismatch))
    if pairs < 100 or mismatch > 1e-3:
        return fail("the quaternion and the orientation of a step disagree (or too few pairs)")
    if len(reports) < 100:
        return fail("only %d orientation reports" % len(reports))
    frets = [l for l in lines if l.startswith("gesture: fret")]
    print("gesture reports: %d 'fret'" % len(frets))
    if len(frets) < 4:   # five poses, each on another fret: at least the four changes
        return fail("fewer than 4 fret gestures for 4 changes of fret")
    status = [l for l in lines if l.startswith("status:")]
    print("status lines: " + " | ".join(status[-2:]))
    failures = 0
    ref_x, ref_sr = read_wav(ref)
    pd_x, pd_sr = read_wav(rec)
    print("render: %.2f s at %d Hz; Pd: %.2f s at %d Hz" % (len(ref_x) / ref_sr, ref_sr, len(pd_x) / pd_sr, pd_sr))
    for i, pose in enumerate(POSES):
        t0, t1 = hold_window(i)
        inside = [r for r in reports if t0 * 1000 <= r[0] <= t1 * 1000]
        if len(inside) < 20:
            failures += fail("pose %d: %d reports inside its hold [%.1f, %.1f] s" % (i + 1, len(inside), t0, t1))
            continue
        worst, total = 0.0, 0.0
        for r in inside:
            # The angles of docs/INTERFACES.md "Pose": elevation, azimuth (0..360), roll.
            err = max(abs(r[1] - pose[0]), angle_deg(r[2], pose[1] % 360.0), angle_deg(r[3], pose[2]))
            worst = max(worst, err)
            total += err
        ok = worst <= 3.0
        print("pose %d %s: %d reports, worst error %.6f deg, mean %.6f deg %s"
              % (i + 1, pose, len(inside), worst, total / len(inside), "ok" if ok else "FAIL"))
        failures += 0 if ok else 1
        w0, w1 = hold_window(i, 0.6, 0.6)
        f_ref = pitch_hz(ref_x[int(w0 * ref_sr):int(w1 * ref_sr)], ref_sr)
        f_pd = pitch_hz(pd_x[int(w0 * pd_sr):int(w1 * pd_sr)], pd_sr)
        if f_ref is None or f_pd is None:
            failures += fail("pose %d: silent (render %s Hz, Pd %s Hz)" % (i + 1, f_ref, f_pd))
            continue
        cents = 1200.0 * math.log2(f_pd / f_ref)
        ok = abs(cents) <= 10.0
        print("pose %d pitch: render %.2f Hz, Pd %.2f Hz, %+.2f cents %s" % (i + 1, f_ref, f_pd, cents, "ok" if ok else "FAIL"))
        failures += 0 if ok else 1
    return 1 if failures else 0


def motor_lines(lines, prefix):
    out = []
    for l in lines:
        if l.startswith(prefix + ":"):
            v = [float(s) for s in l.split()[1:]]
            out.append(v)
    return out


def case_motors(args):
    # Everything is sent at logical time 0; Pd quits 1000 ms later: a report seen was within a second.
    code, lines = run_pd(args, os.path.join(args.patches, "patch_motors.pd"),
                         ["cmd scene patch", "cmd simulate", "cmd motors 15 0 0 0 8 0 0 0 3", "end 1000"])
    errors = [l for l in lines if "error" in l.lower()]
    if errors:
        return fail("Pd said:\n  " + "\n  ".join(errors))
    reports = motor_lines(lines, "motors")
    if not reports:
        return fail("no motors reported within a second")

    def wanted(m):
        return (len(m) == 9 and m[0] > 0 and m[4] > 0 and m[8] > 0 and m[0] >= m[4] >= m[8]
                and all(m[k] == 0 for k in (1, 2, 3, 5, 6, 7)))
    good = [m for m in reports if wanted(m)]
    print("%d motors reports within 1 s; first %s; last %s; %d as asked" % (len(reports), reports[0], reports[-1], len(good)))
    if not good:
        return fail("no report had motors 1, 5, 9 on with m1 >= m5 >= m9 and the others 0")
    if not wanted(reports[-1]):
        return fail("the last report is not as asked: %s" % reports[-1])
    stray = [m for m in reports if any(m[k] != 0 for k in (1, 2, 3, 5, 6, 7))]
    if stray:
        return fail("a motor not asked for was on: %s" % stray[0])
    return 0


def case_help(args):
    patches = sorted(glob.glob(os.path.join(args.externals, "*.pd")))
    helps = [p for p in patches if p.endswith("-help.pd")]
    names = {os.path.basename(p) for p in helps}
    if not {"armadillo-help.pd", "armadillo~-help.pd"} <= names:
        return fail("help patches missing in %s: %s" % (args.externals, sorted(names)))
    failures = 0
    for p in patches:
        code, lines = run_pd(args, p, [], extra_open=[os.path.join(args.patches, "quit_after.pd")])
        bad = [l for l in lines if "couldn't create" in l or "error" in l.lower()]
        print("%s: %d lines on stderr, %d problems, exit %d" % (os.path.basename(p), len(lines), len(bad), code))
        for l in bad:
            print("  " + l)
        failures += 1 if bad or code != 0 else 0
    return 1 if failures else 0


BAD = [
    # (object's receive name, message, what the error must say)
    ("cmd", "scene kazoo", "unknown scene 'kazoo'"),
    ("cmd", "port /dev/armadillo-no-such-port", "/dev/armadillo-no-such-port"),
    ("cmd", "motors 1 2 3", "motors takes 9 levels"),
    ("cmd", "motors 1 2 3 4 5 6 7 8 99", "level 9 is 99"),
    ("cmd", "simulate no-such-motion.csv", "no-such-motion.csv"),
    ("cmd", "osc 99999", "port 99999"),
    ("cmd", "arm middle", "'middle'"),
    ("cmd", "calibration no-such-calibration.json", "no-such-calibration.json"),
    ("cmd", "format klingon", "unknown format 'klingon'"),
    ("cmd", "param theremin.nothing 3", "theremin.nothing"),
    ("cmd", "frobnicate", "unknown message 'frobnicate'"),
    ("cmdt", "scene kazoo", "unknown scene 'kazoo'"),
    ("cmdt", "port /dev/armadillo-no-such-port", "/dev/armadillo-no-such-port"),
    ("cmdt", "motors 1", "motors takes 9 levels"),
    ("cmdt", "simulate no-such-motion.csv", "no-such-motion.csv"),
]


def case_errors(args):
    sends = ["pd dsp 1", "cmd scene patch", "cmd simulate", "cmdt scene patch", "cmdt simulate"]
    sends += ["%s %s" % (r, m) for r, m, _ in BAD]
    # After every bad message the objects still take good ones: the last targets must be felt.
    sends += ["cmd motors 0 0 7 0 0 0 0 0 0", "cmdt motors 0 0 0 0 0 0 0 0 4", "end 1500"]
    code, lines = run_pd(args, os.path.join(args.patches, "bad_messages.pd"), sends)
    errors = [l for l in lines if l.startswith("error:")]
    failures = 0
    for receiver, message, says in BAD:
        obj = "armadillo~:" if receiver == "cmdt" else "armadillo:"
        hit = [e for e in errors if obj in e and says in e]
        print("%-10s %-40s -> %s" % (receiver, message, hit[0] if hit else "NO ERROR"))
        failures += 0 if hit else 1
    if len(errors) != len(BAD):
        failures += fail("%d errors for %d bad messages:\n  %s" % (len(errors), len(BAD), "\n  ".join(errors)))
    for prefix, want in (("motors", 2), ("tmotors", 8)):
        reports = motor_lines(lines, prefix)
        last = reports[-1] if reports else None
        ok = last is not None and last[want] > 0 and all(last[k] == 0 for k in range(9) if k != want)
        print("%s: %d reports, last %s %s" % (prefix, len(reports), last, "ok" if ok else "FAIL"))
        failures += 0 if ok else 1
    for prefix in ("status", "tstatus"):
        st = [l for l in lines if l.startswith(prefix + ":")]
        print("%s: %s" % (prefix, st[-1] if st else "none"))
        if not st or "simulate connected" not in st[-1]:
            failures += fail("%s: the source did not keep running" % prefix)
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["theremin", "motors", "help", "errors"])
    ap.add_argument("--pd", required=True)
    ap.add_argument("--externals", required=True)
    ap.add_argument("--patches", required=True)
    ap.add_argument("--armadillo", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--preload", action="append", default=[],
                    help="a sanitizer runtime Pd loads first (an instrumented build of the objects)")
    args = ap.parse_args()
    for name in ("externals", "patches", "armadillo", "work"):
        setattr(args, name, os.path.abspath(getattr(args, name)))
    os.makedirs(args.work, exist_ok=True)
    os.chdir(args.work)
    rc = {"theremin": case_theremin, "motors": case_motors, "help": case_help, "errors": case_errors}[args.case](args)
    print("PASS" if rc == 0 else "FAILED")
    return rc


if __name__ == "__main__":
    sys.exit(main())
