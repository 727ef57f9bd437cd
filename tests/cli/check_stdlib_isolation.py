#!/usr/bin/env python3
"""A scene's C++ holds nothing of the modules it does not use.

    check_stdlib_isolation.py PARTC STDLIB WORK SCENE...

Two copies of the standard library are laid side by side, WORK/base/stdlib
and WORK/more/stdlib, the second with a twin of every module beside it (the
same text under another module name, so every effect, function and
parameter name of the library is declared twice). For each scene:
- its C++ with the larger library equals its C++ with the library as it is,
  byte for byte once the copies' folder names are swapped (both are four
  letters long, so no comment's alignment moves): adding modules changes
  nothing;
- for each module the scene does not open (partc --explain lists those it
  does), no identifier of the C++ is one that module would bring: its
  functions (MODULE_NAME_fn) or an instance of one of its effects under the
  effect's own name (EFFECT_param, EFFECT_local), unless the scene keeps an
  instance of that name.
"""
import re
import shutil
import subprocess
import sys
from pathlib import Path


def modules_of(root):
    """dotted name -> (file, text) for every module under root."""
    out = {}
    for path in sorted(root.rglob("*.part")):
        text = path.read_text()
        match = re.search(r"^module\s+([\w.]+)", text, re.MULTILINE)
        if match:
            out[match.group(1)] = (path, text)
    return out


def brought_names(module, text):
    """The C++ identifiers a module's declarations would become."""
    names = {module.replace(".", "_") + "_" + fn
             for fn in re.findall(r"^fn\s+(\w+)", text, re.MULTILINE)}
    for effect, params, body in re.findall(r"^effect\s+(\w+)\((.*?)\)[^{]*\{(.*?)^\}", text,
                                           re.MULTILINE | re.DOTALL):
        for name in re.findall(r"(?:^|,)\s*(?:const\s+)?(\w+)\s*:", params):
            names.add((effect, f"{effect}_{name}"))
        for name in re.findall(r"owns\s+local\s+(?:mirrored\s+)?(\w+)", body):
            names.add((effect, f"{effect}_{name}"))
    return names


def partc(program, scene, *args):
    run = subprocess.run([program, scene, *args], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"partc {scene} {' '.join(args)} failed:\n{run.stderr}")
    return run.stdout


def main():
    program, stdlib, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    scenes = sys.argv[4:]
    base, more = work / "base" / "stdlib", work / "more" / "stdlib"
    shutil.rmtree(work, ignore_errors=True)
    shutil.copytree(stdlib, base)
    shutil.copytree(stdlib, more)
    library = modules_of(stdlib)
    for module, (path, text) in library.items():
        twin = more / path.relative_to(stdlib).with_name(path.stem + "_twin.part")
        twin.write_text(re.sub(r"^module\s+([\w.]+)", rf"module {module}_twin", text, count=1,
                               flags=re.MULTILINE))
    print(f"{len(library)} modules; the larger library holds {2 * len(library)}")

    failures = []
    for scene in scenes:
        cpp = partc(program, scene, "--stdlib", str(base))
        larger = partc(program, scene, "--stdlib", str(more))
        same = larger.replace(f"{work}/more/stdlib/", f"{work}/base/stdlib/") == cpp
        if not same:
            failures.append(f"{scene}: its C++ changes when modules are added to the library")
        explain = partc(program, scene, "--stdlib", str(base), "--explain")
        opened_block = re.search(r"^modules opened.*?\n((?:  .*\n)*)", explain, re.MULTILINE)
        opened = {Path(line.strip()).resolve() for line in opened_block.group(1).splitlines()}
        kept_block = re.search(r"^effects kept:\n((?:  .*\n)*)", explain, re.MULTILINE)
        kept = {line.split()[0] for line in kept_block.group(1).splitlines()} if kept_block else set()
        identifiers = set(re.findall(r"\b[A-Za-z_]\w*\b", cpp))
        unopened = [m for m, (path, _) in library.items()
                    if (base / path.relative_to(stdlib)).resolve() not in opened]
        leaked = []
        for module in unopened:
            for name in brought_names(module, library[module][1]):
                if isinstance(name, tuple):
                    effect, name = name
                    if effect in kept:
                        continue
                if name in identifiers:
                    leaked.append(f"{name} (from {module})")
        print(f"{scene}: {len(opened)} modules opened, {len(unopened)} not; "
              f"C++ {'identical' if same else 'CHANGED'} with the larger library; "
              f"{len(leaked)} identifiers of unopened modules")
        if leaked:
            failures.append(f"{scene}: identifiers of modules it does not open: {', '.join(leaked)}")
        if len(opened) + len(unopened) != len(library):
            failures.append(f"{scene}: --explain lists modules outside the library: {opened}")
    if failures:
        sys.exit("FAILED:\n" + "\n".join(failures))


if __name__ == "__main__":
    main()
