#!/usr/bin/env python3
"""The AVX2 copy of the dense kernels (libstm/geometry/dense_front_avx2.cpp) must define no global
or weak symbol that does not name its own namespaces: an inline function or template it emitted
under a shared name could be merged by the linker with the baseline's copy, and a processor without
AVX2 would then run AVX2 instructions. Usage: check_kernel_symbols.py OBJECT_FILE... (the one named
*dense_front_avx2* is checked; exit 1 naming each stray symbol)."""
import subprocess
import sys

# A name safe from merging mentions one of the renamed namespaces somewhere (a template of the
# standard library instantiated on a renamed Eigen type is as unique as the type); DW.ref. symbols
# are the exception tables' pointers to the personality routine, the same in every object.
OWN = ("sdm_avx2_eigen::", "sdm::avx2::")


def main(paths):
    objects = [p for p in paths if "dense_front_avx2" in p]
    if len(objects) != 1:
        print(f"expected one dense_front_avx2 object among {len(paths)} files, found {len(objects)}")
        return 1
    out = subprocess.run(["nm", "-C", "--defined-only", objects[0]], check=True, capture_output=True, text=True).stdout
    stray = []
    for line in out.splitlines():
        parts = line.split(maxsplit=2)
        if len(parts) < 3:
            continue
        kind, name = parts[1], parts[2]
        if kind.islower() and kind not in ("u", "v", "w"):  # local symbols cannot be merged
            continue
        if not name.startswith("DW.ref.") and not any(own in name for own in OWN):
            stray.append(f"{kind} {name}")
    for s in stray:
        print("shared symbol in the AVX2 kernels:", s)
    print(f"{objects[0]}: {len(stray)} stray symbol(s)")
    return 1 if stray else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
