"""Where a Newmark step's time goes, by compiled function and by source line (needs Linux ``perf``).

numba's machine code has no symbols ``perf`` can read. This script compiles the kernels with debug
line tables into a fresh cache (``NUMBA_DEBUGINFO=1``), keeps the loop's assembly, then runs model b
under ``perf record`` from that cache (nothing compiled while sampling), with a perf map naming every
compiled function. The samples inside the loop ``_integrate`` are mapped to source lines by aligning
its disassembled machine code with the assembly's instruction sequence. Line numbers are those of the
source file of the inlined function that emitted the instruction (the file name is not kept).

    python benchmarks/profile_lines.py                      # elastic stories
    python benchmarks/profile_lines.py --stories takeda --repeats 30 --top 30
    python benchmarks/profile_lines.py --gaps-open           # contact-free steps only

A debug build runs 10-40 % slower than the default one; read the shares, not the absolute times.
"""

from __future__ import annotations

import argparse
import collections
import ctypes
import dataclasses
import difflib
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def _child(args: argparse.Namespace, work: Path) -> None:
    """In the profiled process: run model b, write the perf map, the loop's code and assembly."""
    from _common import fixed_step
    from models import DURATION, build, record

    from pounding import Stories, assemble
    from pounding.integrators import _kernels
    from pounding.simulate import AnalysisOptions, run

    gm, _ = record()
    system = build("b", "lankarani_nikravesh")
    buildings = system.buildings
    if args.stories != "elastic":
        st = Stories(args.stories, {"yield_drift": 0.005, "hardening": 0.03})
        buildings = [dataclasses.replace(b, stories=st) for b in buildings]
    contacts = system.contacts
    if args.gaps_open:
        contacts = [dataclasses.replace(c, gap=2.0) for c in contacts]
    system = assemble(buildings, contacts)
    opts = AnalysisOptions(**fixed_step(args.dt), duration=DURATION)
    run(system, gm, opts)
    cres = _kernels._integrate.overloads[_kernels._integrate.signatures[0]]
    asm_path = work / "integrate.s"
    if not asm_path.exists():  # the compiling pass: the cached code has no assembly to show
        asm_path.write_text(cres.library.get_asm_str())
        return
    from numba.core.registry import cpu_target

    engine = cpu_target.target_context.codegen()._engine._ee
    names = sorted(set(re.findall(r"^(_ZN[^:\s]+):", asm_path.read_text(), re.M)))
    rows = sorted((engine.get_function_address(n), n) for n in names)
    rows = [r for r in rows if r[0]]
    loop = cres.fndesc.mangled_name
    with open(f"/tmp/perf-{os.getpid()}.map", "w") as f:
        for (address, name), (after, _) in zip(
            rows, [*rows[1:], (rows[-1][0] + 65536, "")], strict=True
        ):
            short = "_".join(re.findall(r"\d+([a-z_][a-z_0-9]+)", name[:150])[:4])
            f.write(f"{address:x} {after - address:x} {short}\n")
            if name == loop:
                (work / f"loop_{address:x}.bin").write_bytes(
                    ctypes.string_at(address, after - address)
                )
    (work / "steps").write_text(str(args.repeats * round(DURATION / args.dt)))
    for _ in range(args.repeats):
        run(system, gm, opts)


def _instructions(asm: str, name: str) -> list[tuple[str, int]]:
    """(mnemonic, source line) of each instruction of function ``name`` in LLVM's assembly."""
    lines = asm.split("\n")
    start = next(i for i, line in enumerate(lines) if line.startswith(name + ":"))
    out, loc = [], 0
    for line in lines[start + 1 :]:
        s = line.strip()
        if s.startswith(".Lfunc_end"):
            break
        m = re.match(r"\.loc\s+\d+\s+(\d+)", s)
        if m:
            loc = int(m.group(1))
        elif s and not s.startswith((".", "#")) and not s.endswith(":"):
            out.append((s.split()[0], loc))
    return out


def _report(args: argparse.Namespace, work: Path, data: Path) -> None:
    code = next(work.glob("loop_*.bin"))
    base = int(code.stem.split("_")[1], 16)
    steps = int((work / "steps").read_text())
    rate = args.frequency
    report = subprocess.run(["perf", "report", "-i", str(data), "--sort", "sym", "--stdio", "-n"],
                            capture_output=True, text=True).stdout  # fmt: skip
    print(f"model b, {args.stories} stories, dt {args.dt}, {steps} steps; ns per step by function:")
    for line in report.splitlines():
        parts = line.split()
        if len(parts) >= 4 and not line.startswith("#") and "pounding" in parts[-1]:
            print(f"  {int(parts[1]) / rate / steps * 1e9:7.1f}  {parts[-1]}")
    dis = subprocess.run(["objdump", "-D", "-b", "binary", "-mi386:x86-64",
                          f"--adjust-vma={base:#x}", str(code)],
                         capture_output=True, text=True).stdout  # fmt: skip
    addresses, mnemonics = [], []
    for line in dis.splitlines():
        parts = line.split("\t")
        if re.match(r"\s+[0-9a-f]+:", line) and len(parts) >= 3 and parts[2].split():
            addresses.append(int(parts[0].strip()[:-1], 16))
            mnemonics.append(parts[2].split()[0])
    loop = re.search(r"^(_ZN\d+pounding11integrators8_kernels10_integrate[^:\s]*):",
                     (work / "integrate.s").read_text(), re.M).group(1)  # fmt: skip
    ins = _instructions((work / "integrate.s").read_text(), loop)
    matcher = difflib.SequenceMatcher(None, [m[:3] for m, _ in ins], [m[:3] for m in mnemonics],
                                      autojunk=False)  # fmt: skip
    line_of = {}
    for block in matcher.get_matching_blocks():
        for k in range(block.size):
            line_of[addresses[block.b + k]] = ins[block.a + k][1]
    ips = subprocess.run(["perf", "script", "-i", str(data), "-F", "ip"], capture_output=True,
                         text=True).stdout.split()  # fmt: skip
    per_line = collections.Counter(line_of[int(ip, 16)] for ip in ips if int(ip, 16) in line_of)
    total = sum(per_line.values())
    print(f"inside the loop, by source line ({total} samples; line 0: no line recorded):")
    for line, count in per_line.most_common(args.top):
        print(f"  {count / rate / steps * 1e9:7.1f} ns  {100 * count / total:5.1f} %  line {line}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--stories", default="elastic")
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--frequency", type=int, default=4999, help="perf samples per second")
    ap.add_argument("--top", type=int, default=25)
    ap.add_argument("--gaps-open", action="store_true")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args, Path(args.child))
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        env = {**os.environ, "NUMBA_DEBUGINFO": "1", "NUMBA_CACHE_DIR": str(work / "cache")}
        child = [sys.executable, __file__, *(argv if argv is not None else sys.argv[1:]),
                 "--child", str(work)]  # fmt: skip
        subprocess.run(child, env=env, check=True, stderr=subprocess.DEVNULL)  # compile
        data = work / "perf.data"
        subprocess.run(["perf", "record", "-q", "-F", str(args.frequency), "-o", str(data), *child],
                       env=env, check=True, stderr=subprocess.DEVNULL)  # fmt: skip
        _report(args, work, data)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
