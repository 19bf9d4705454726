#!/usr/bin/env python3
"""List the functions and files of the C++ sources that are longer than a limit.

    python3 scripts/function_sizes.py                 # functions over 120 lines, files over 800
    python3 scripts/function_sizes.py --lines 60 src/gridshell/pipeline
    python3 scripts/function_sizes.py --top 10        # the ten longest functions, whatever their size
    python3 scripts/function_sizes.py --check         # exit 1 when anything is over (for CI)

A function's length is counted from the line of its name to the line of its closing brace, blank
lines and comments included (what a reader scrolls through). The scan matches braces after
removing comments, strings and character literals; a brace block counts as a function when the
text in front of it ends in a parameter list (optionally followed by const, noexcept, override,
a trailing return type or a constructor's initializer list). Lambdas count towards the function
that holds them; classes, structs and namespaces are looked into.
"""
import argparse
import re
import sys
from pathlib import Path

SOURCE_SUFFIXES = {".cpp", ".h", ".hpp", ".cc"}
SCOPE_WORDS = re.compile(r"^(?:template\s*<.*>\s*)?(?:inline\s+)?(namespace|struct|class|union)\b"
                         r"|^extern\s+\"C\"", re.S)
NOT_FUNCTION_WORDS = re.compile(r"^(?:typedef\s+)?(?:enum)\b")
FUNCTION_TAIL = re.compile(
    r"\)\s*(?:const\b\s*|noexcept\b\s*(?:\([^()]*\))?\s*|override\b\s*|final\b\s*|&&?\s*|"
    r"->\s*[\w:<>,\s*&]+?\s*|mutable\b\s*)*$", re.S)


def strip_comments_and_literals(text):
    """The text with comments, strings and character literals blanked (newlines kept)."""
    out = []
    i, n = 0, len(text)
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
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and (text[i - 1].isalnum()):  # digit separator 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def strip_preprocessor(text):
    return re.sub(r"(?m)^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", lambda m: re.sub(r"[^\n]", " ", m.group(0)),
                  text)


def matching_brace(text, open_index):
    depth = 0
    for k in range(open_index, len(text)):
        if text[k] == "{":
            depth += 1
        elif text[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    return len(text) - 1


def function_name(header):
    """The qualified name in front of the outermost parameter list of a function header."""
    depth = 0
    for k in range(len(header) - 1, -1, -1):
        if header[k] == ")":
            depth += 1
        elif header[k] == "(":
            depth -= 1
            if depth == 0:
                m = re.search(r"([~\w:]+(?:operator\s*[^\s(]+)?)\s*$", header[:k])
                if m and m.group(1) not in {"if", "for", "while", "switch", "catch", "return"}:
                    # an initializer list: keep looking left for the constructor's own ()
                    before = header[:m.start()].rstrip()
                    if before.endswith((":", ",")) and not before.endswith("::"):
                        continue
                    return m.group(1)
                return None
    return None


def scan(text, start, end, out, line_of):
    """Collect (name, first line, last line) of the functions between start and end."""
    header_start = start
    k = start
    while k < end:
        c = text[k]
        if c in ";}":
            header_start = k + 1
        elif c == "{":
            header = text[header_start:k].strip()
            close = matching_brace(text, k)
            if SCOPE_WORDS.match(header):
                scan(text, k + 1, close, out, line_of)
            elif NOT_FUNCTION_WORDS.match(header) or "(" not in header:
                pass
            else:
                # a constructor's initializer list ends in name{...}: skip braced members
                name = None
                if FUNCTION_TAIL.search(header) or re.search(r"\)\s*:\s*[\s\S]*[)}]\s*$",
                                                              header):
                    name = function_name(header)
                if name and not re.search(r"=\s*[^=]*$", header.split("(")[0]):
                    first = line_of(header_start + (len(text[header_start:k]) -
                                                    len(text[header_start:k].lstrip())))
                    out.append((name, first, line_of(close)))
                elif name is None and re.search(r"[\w>]\s*$", header) and ")" in header:
                    # braced member initializer inside an initializer list: not a block end
                    k = close + 1
                    continue
            k = close + 1
            header_start = k
            continue
        k += 1


def functions_of(path):
    raw = path.read_text(encoding="utf-8", errors="replace")
    text = strip_preprocessor(strip_comments_and_literals(raw))
    starts = [0]
    for m in re.finditer("\n", text):
        starts.append(m.end())

    def line_of(index):
        lo, hi = 0, len(starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if starts[mid] <= index:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    out = []
    scan(text, 0, len(text), out, line_of)
    return out, raw.count("\n") + (0 if raw.endswith("\n") else 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="*", default=["src"], help="files or folders (default src)")
    parser.add_argument("--lines", type=int, default=120, help="function limit (default 120)")
    parser.add_argument("--file-lines", type=int, default=800, help="file limit (default 800)")
    parser.add_argument("--top", type=int, default=0, help="list the N longest functions instead")
    parser.add_argument("--check", action="store_true", help="exit 1 when anything is over")
    args = parser.parse_args()

    files = []
    for p in map(Path, args.paths):
        if p.is_dir():
            files += sorted(f for f in p.rglob("*") if f.suffix in SOURCE_SUFFIXES)
        else:
            files.append(p)
    rows, long_files = [], []
    for f in files:
        functions, lines = functions_of(f)
        if lines > args.file_lines:
            long_files.append((lines, str(f)))
        rows += [(last - first + 1, f"{f}:{first}", name) for name, first, last in functions]
    rows.sort(key=lambda r: (-r[0], r[1]))
    over = [r for r in rows if r[0] > args.lines]
    shown = rows[:args.top] if args.top else over
    for length, where, name in shown:
        print(f"{length:5d}  {where}  {name}")
    for lines, f in sorted(long_files, reverse=True):
        print(f"{lines:5d}  {f}  (file over {args.file_lines} lines)")
    if not args.top:
        print(f"{len(rows)} functions in {len(files)} files; {len(shown)} over {args.lines} lines, "
              f"{len(long_files)} files over {args.file_lines}", file=sys.stderr)
    return 1 if args.check and (over or long_files) else 0


if __name__ == "__main__":
    sys.exit(main())
