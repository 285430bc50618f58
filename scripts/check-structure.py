#!/usr/bin/env python3
"""The structure rules of docs/ARCHITECTURE.md ("One instrument", issue 45), checked from the code.

  python3 scripts/check-structure.py [--max-function-lines N] [--report-only]

Prints, for Source/:
  - every function (or constructor) longer than N lines (default 150), from the line its
    signature starts to its closing brace, and
  - every mention of a concrete source or sink class in Source/Cli, Source/Plugin and Source/Pd
    (the front ends ask the live session with a description instead; in Source/Pd one fails), and
  - every file that runs the control step (calls ControlLoop::tick): one file should, and
  - every place a source of the instrument is constructed outside the one file allowed for its
    class (the source registry, Live/Sources/SourceRegistry.cpp; the position sources in
    Navigation/NavigationRig.cpp, the one place that knows a route), and
  - every data member of Plugin/PluginProcessor.h whose type is of a core room's namespace
    (armadillo::live, ::link, ::access, ...; `using` aliases of such types in Source/Plugin
    count too): the processor holds the instrument and its clock, not its parts (at most 3).
Exits 1 when a function is too long, a file other than Live/Step/StepRunner.cpp runs the control step,
a source is constructed outside its one place, or the processor holds more than 3 core objects, unless --report-only; the concrete names are
counted on the last line, so their progress is visible in every run.
Comments, string and character literals are skipped; the brace matcher counts a '{' whose
preceding declaration holds a '(' at namespace or class scope as a function body."""
import argparse
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONCRETE = ["DeviceLink", "OscReceiver", "OscSender", "SimulatedForearm", "WalkerSim", "GpsdSource",
            "OscPositionSource", "MqttClient", "MessageService", "TactorOutput", "SoundCard", "SequencerOut"]

# Where each source class of the instrument may be constructed (one place per class, issue 45).
REGISTRY = "Source/Live/Sources/SourceRegistry.cpp"
SOURCE_CONSTRUCTED_IN = {"DeviceLink": REGISTRY, "OscReceiver": REGISTRY, "SimulatedForearm": REGISTRY,
                         "MessageService": REGISTRY, "GpsdSource": "Source/Navigation/NavigationRig.cpp",
                         "OscPositionSource": "Source/Navigation/NavigationRig.cpp"}


def constructions(code, cls):
    """Line numbers where `code` constructs a `cls`: make_unique/make_shared, new, or an object."""
    q = r"(?:\w+::)*" + cls
    pattern = re.compile(r"make_(?:unique|shared)\s*<\s*" + q + r"\s*>|\bnew\s+" + q + r"\b|(?<![\w:<*&])" + q + r"\s+\w+\s*[({]")
    return [code.count("\n", 0, m.start()) + 1 for m in pattern.finditer(code)]


def strip_code(text):
    """The text with comments, literals and preprocessor lines blanked (newlines kept, so line
    numbers hold)."""
    text = re.sub(r"(?m)^[ \t]*#.*$", lambda m: " " * len(m.group(0)), text)
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * max(0, j - i - 2) + (c if j - i >= 2 else ""))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(code):
    """(start line, end line, name) of every outermost function body."""
    found = []
    stack = []          # 'ns', 'class', 'func', 'block'
    decl_start = 0      # index where the current declaration began
    line_of = []
    line = 1
    for ch in code:
        line_of.append(line)
        if ch == "\n":
            line += 1
    func_open = None
    for i, ch in enumerate(code):
        if ch in ";":
            if not stack or stack[-1] in ("ns", "class"):
                decl_start = i + 1
        elif ch == "{":
            if not stack or stack[-1] in ("ns", "class"):
                decl = code[decl_start:i]
                head = decl.strip()
                if re.search(r"\b(namespace|extern\s*$)", head) and "(" not in head:
                    stack.append("ns")
                elif re.match(r"^(template\s*<.*>\s*)?(class|struct|union|enum)\b", head, re.S) and "(" not in head.split(":")[0]:
                    stack.append("class")
                elif head.startswith("extern \"") or head == "extern":
                    stack.append("ns")
                elif "(" in head and not re.search(r"=\s*$", head):
                    stack.append("func")
                    m = re.findall(r"([~\w:]+)\s*\(", head)
                    name = m[0] if m else "?"
                    offset = len(decl) - len(decl.lstrip())
                    func_open = (line_of[decl_start + offset] if decl_start + offset < len(line_of) else line_of[i], name)
                else:
                    stack.append("block")
            else:
                stack.append("block")
        elif ch == "}":
            kind = stack.pop() if stack else "block"
            if kind == "func" and func_open is not None:
                found.append((func_open[0], line_of[i], func_open[1]))
                func_open = None
            if not stack or stack[-1] in ("ns", "class"):
                decl_start = i + 1
    return found


# The front ends: they drive a clock and present; they ask the instrument with a description. In
# those listed as strict (born after issue 45: Pure Data's objects) a concrete class fails the check.
FRONT_ENDS = ["Cli", "Plugin", "Pd"]
STRICT_FRONT_ENDS = ["Pd"]

CORE_ROOMS = ["access", "audio", "braille", "core", "engine", "follow", "formats", "fusion", "instruments", "link",
              "live", "mapping", "mqtt", "navigation", "osc", "procedures", "tactile", "tactors"]
MAX_PROCESSOR_CORE_OBJECTS = 3


def processor_core_members(src):
    """(line, type, name) of each data member of the plugin processor whose type is a core room's."""
    aliases = set()
    plugin = os.path.join(src, "Plugin")
    rooms = "|".join(CORE_ROOMS)
    for path in source_files(plugin):
        with open(path, encoding="utf-8", errors="replace") as f:
            code = strip_code(f.read())
        aliases.update(re.findall(r"\busing\s+(?:" + rooms + r")::(\w+)\s*;", code))
        aliases.update(re.findall(r"\busing\s+(\w+)\s*=\s*(?:" + rooms + r")::", code))
    path = os.path.join(plugin, "PluginProcessor.h")
    if not os.path.exists(path):
        return []
    with open(path, encoding="utf-8", errors="replace") as f:
        code = strip_code(f.read())
    found = []
    member = re.compile(r"^\s*(?:mutable\s+)?((?:std::(?:unique_ptr|shared_ptr|optional)<\s*)?([\w:]+)(?:\s*>)?)\s+(\w+_)\s*(?:[{=;]|\{)")
    for lineno, text in enumerate(code.split("\n"), 1):
        m = member.match(text)
        if not m:
            continue
        type_name = m.group(2)
        room = type_name.split("::")[0] if "::" in type_name else None
        if (room in CORE_ROOMS) or (room is None and type_name in aliases):
            found.append((lineno, m.group(1).strip(), m.group(3)))
    return found


def source_files(folder):
    for base, _, names in os.walk(folder):
        for name in sorted(names):
            if name.endswith((".cpp", ".h")):
                yield os.path.join(base, name)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--max-function-lines", type=int, default=150)
    ap.add_argument("--report-only", action="store_true")
    args = ap.parse_args()
    src = os.path.join(ROOT, "Source")
    long_functions, concrete, ticks, misplaced = [], [], [], []
    for path in source_files(src):
        rel = os.path.relpath(path, ROOT)
        with open(path, encoding="utf-8", errors="replace") as f:
            code = strip_code(f.read())
        for start, end, name in functions(code):
            if end - start + 1 > args.max_function_lines:
                long_functions.append((end - start + 1, rel, start, name))
        for cls, allowed in SOURCE_CONSTRUCTED_IN.items():
            if os.path.basename(rel) in (cls + ".cpp", cls + ".h") or rel == allowed:
                continue
            for lineno in constructions(code, cls):
                misplaced.append((rel, lineno, cls, allowed))
        front_end = any(rel.startswith(os.path.join("Source", f)) for f in FRONT_ENDS)
        for lineno, text in enumerate(code.split("\n"), 1):
            if front_end:
                for cls in CONCRETE:
                    if re.search(r"\b" + cls + r"\b", text):
                        concrete.append((rel, lineno, cls))
            if not rel.endswith("ControlLoop.cpp") and re.search(r"\bloop_?(\(\))?\s*(\.|->)\s*tick\s*\(", text):
                ticks.append((rel, lineno))
        if front_end:
            with open(path, encoding="utf-8", errors="replace") as f:
                for lineno, text in enumerate(f, 1):
                    m = re.match(r'\s*#\s*include\s*"[^"]*/(\w+)\.h"', text)
                    if m and m.group(1) in CONCRETE:
                        concrete.append((rel, lineno, m.group(1) + ".h"))
    for n, rel, start, name in sorted(long_functions, reverse=True):
        print(f"function longer than {args.max_function_lines} lines: {rel}:{start} {name} ({n} lines)")
    for rel, lineno, cls in concrete:
        print(f"front end names a concrete source or sink: {rel}:{lineno} {cls}")
    for rel, lineno, cls, allowed in misplaced:
        print(f"constructs a source outside its one place: {rel}:{lineno} {cls} (only in {allowed})")
    for rel, lineno in ticks:
        print(f"runs the control step (ControlLoop::tick): {rel}:{lineno}")
    members = processor_core_members(src)
    for lineno, type_name, name in members:
        print(f"processor holds a core object: Source/Plugin/PluginProcessor.h:{lineno} {type_name} {name}")
    tick_files = {rel for rel, _ in ticks}
    stray_ticks = sorted(t for t in tick_files if not t.endswith(os.path.join("Live", "Step", "StepRunner.cpp")))
    files = len({rel for rel, _, _ in concrete})
    print(f"structure: {len(long_functions)} functions over {args.max_function_lines} lines, "
          f"{len(concrete)} mentions of concrete sources or sinks in {files} front-end files, {len(tick_files)} files that run the control step, "
          f"{len(members)} core objects in the plugin processor, {len(misplaced)} sources constructed outside their one place")
    strict = [c for c in concrete if any(c[0].startswith(os.path.join("Source", f)) for f in STRICT_FRONT_ENDS)]
    failed = long_functions or stray_ticks or strict or misplaced or len(members) > MAX_PROCESSOR_CORE_OBJECTS
    return 1 if failed and not args.report_only else 0


if __name__ == "__main__":
    sys.exit(main())
