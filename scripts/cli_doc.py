#!/usr/bin/env python3
"""Keeps docs/CLI.md, the command reference, in step with `sdm --help`.

    scripts/cli_doc.py --check BUILD/sdm [REPOSITORY]   (the test readme.cli_reference)
    scripts/cli_doc.py --write BUILD/sdm [REPOSITORY]   (after adding or changing an option)

Every command that `sdm --help` lists (its subcommands, and `sdm batch`, which its last line names)
has a section "## sdm COMMAND" in docs/CLI.md: prose written by hand, then the command's options as
its --help gives them, between the markers

    <!-- options of `sdm COMMAND --help`: scripts/cli_doc.py --write; not edited by hand -->
    <!-- end of options -->

--write regenerates every such list from --help (and adds a section, with the command's
one-line description as its prose, for a command that has none); the prose is left alone.
--check fails, naming the command and the option, when a command has no section, when a section
lacks an option of its --help, or when a list differs from what --write would write.
"""
import os
import re
import subprocess
import sys

BEGIN = "<!-- options of `sdm {}"
BEGIN_LINE = "<!-- options of `sdm {} --help`: scripts/cli_doc.py --write; not edited by hand -->"
END_LINE = "<!-- end of options -->"


def run_help(sdm, args):
    env = dict(os.environ, COLUMNS="100")  # argparse (sdm batch) wraps to the terminal's width
    r = subprocess.run([sdm] + args + ["--help"], capture_output=True, text=True, env=env, timeout=120)
    if r.returncode != 0:
        sys.exit(f"cli_doc: '{' '.join(['sdm'] + args)} --help' exited {r.returncode}: {r.stderr.strip()}")
    return r.stdout


def commands(sdm):
    """The subcommands `sdm --help` lists, in its order, then those its last lines name (sdm batch)."""
    text = run_help(sdm, [])
    names, in_list = [], False
    for line in text.splitlines():
        if line.strip() == "Subcommands:":
            in_list = True
        elif in_list and re.match(r"^  \S", line):
            names.append(line.split()[0])
        elif in_list and line and not line.startswith(" "):
            in_list = False
    for name in re.findall(r"\bsdm (\w+) --help", text):
        if name not in names:
            names.append(name)
    return names


def options(help_text):
    """[(spec, description)] of the Positionals/Options (CLI11) or positional arguments/options
    (argparse) of a --help text, --help itself left out; wrapped lines joined."""
    entries, in_list = [], False
    for line in help_text.splitlines():
        if re.match(r"^(Positionals|Options|positional arguments|options):$", line):
            in_list = True
            continue
        if not in_list:
            continue
        if not line.strip() or not line.startswith(" "):
            in_list = False
            continue
        m = re.match(r"^  (\S.*?)(?:\s{2,}(\S.*))?$", line)
        if m and not re.match(r"^\s{4,}", line):
            entries.append([m.group(1).strip(), (m.group(2) or "").strip()])
        elif entries:
            entries[-1][1] = (entries[-1][1] + " " + line.strip()).strip()
    return [(s, d) for s, d in entries if not re.match(r"^-h,\s?--help$", s)]


def option_names(spec):
    """The names a reader looks for: --output and -o of '-o,--output TEXT REQUIRED'; the name of a positional."""
    names = re.findall(r"(?<![\w-])(--?[A-Za-z][\w-]*)", spec)
    return names or [spec.split()[0]]


def block(name, entries):
    lines = [BEGIN_LINE.format(name)]
    for spec, description in entries:
        lines.append(f"- `{spec}`" + (f": {description}" if description else ""))
    lines.append(END_LINE)
    return "\n".join(lines)


def sections(text):
    """{command: (start, end)} of the '## sdm COMMAND' sections of CLI.md (character offsets)."""
    heads = [(m.group(1), m.start()) for m in re.finditer(r"^## sdm (\w+)\s*$", text, re.M)]
    ends = [m.start() for m in re.finditer(r"^## ", text, re.M)] + [len(text)]
    return {name: (start, min(e for e in ends if e > start)) for name, start in heads}


def regenerate(text, name, entries):
    """CLI.md with the options list of `name`'s section replaced (added at its end when missing)."""
    start, end = sections(text)[name]
    section = text[start:end]
    new = block(name, entries)
    b = section.find(BEGIN.format(name))
    if b >= 0:
        e = section.index(END_LINE, b) + len(END_LINE)
        section = section[:b] + new + section[e:]
    else:
        section = section.rstrip("\n") + "\n\n" + new + "\n\n"
    return text[:start] + section + text[end:]


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ("--check", "--write"):
        sys.exit(__doc__)
    mode, sdm = sys.argv[1], os.path.abspath(sys.argv[2])
    repo = os.path.abspath(sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(__file__), ".."))
    path = os.path.join(repo, "docs", "CLI.md")
    text = open(path, encoding="utf-8").read()
    fix = f"run 'python3 scripts/cli_doc.py --write {sys.argv[2]}' from the repository and describe the change in the section's prose"
    problems = []
    new_text = text
    for name in commands(sdm):
        entries = options(run_help(sdm, [name]))
        if name not in sections(new_text):
            problems.append(f"docs/CLI.md has no section '## sdm {name}' for a command 'sdm --help' lists")
            if mode == "--write":
                summary = run_help(sdm, [name]).split("\nUsage:")[0].strip() if name != "batch" else ""
                new_text = new_text.rstrip("\n") + f"\n\n## sdm {name}\n\n{summary}\n"
            else:
                continue
        start, end = sections(new_text)[name]
        section = new_text[start:end]
        for spec, _ in entries:
            for option in option_names(spec):
                if not re.search(r"(?<![\w-])" + re.escape(option) + r"(?![\w-])", section):
                    problems.append(f"docs/CLI.md, section 'sdm {name}': no {option} (from 'sdm {name} --help')")
        if block(name, entries) not in section:
            problems.append(f"docs/CLI.md, section 'sdm {name}': its options list differs from 'sdm {name} --help'")
        new_text = regenerate(new_text, name, entries)
    if mode == "--write":
        if new_text != text:
            with open(path + ".tmp", "w", encoding="utf-8") as f:
                f.write(new_text)
            os.replace(path + ".tmp", path)
            print("cli_doc: docs/CLI.md updated from --help; describe new commands and options in their sections' prose")
        else:
            print("cli_doc: docs/CLI.md is current")
        return 0
    for p in problems:
        print(p)
    if problems:
        print(f"cli_doc: docs/CLI.md is not current with 'sdm --help': {fix}.")
        return 1
    print(f"cli_doc: docs/CLI.md has every command of 'sdm --help' and every option of each")
    return 0


if __name__ == "__main__":
    sys.exit(main())
