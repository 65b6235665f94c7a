"""The machine a run computed on, so that two runs' artefacts can be compared by name.

Same commit, same artefacts holds across x86-64 CPUs (``stages.runtime``), not across
architectures or library releases: a comparison that differs needs to say which CPU, which
instruction sets and which numerical libraries each side had.
"""

from __future__ import annotations

import os
import platform
from importlib import metadata
from pathlib import Path

CPUINFO = Path("/proc/cpuinfo")
ISA_FLAGS = ("fma", "avx2", "avx512f")  # the levels the pinned code paths choose among
LIBRARIES = ("numpy", "scipy", "torch", "numba", "exudyn", "scikit-learn")


def cpu(cpuinfo: str | None = None) -> dict[str, str]:
    """Vendor, model name and the instruction-set levels of this CPU (Linux's /proc/cpuinfo;
    ``platform`` elsewhere, where the vendor may be unknown)."""
    if cpuinfo is None:
        cpuinfo = CPUINFO.read_text() if CPUINFO.exists() else ""
    fields: dict[str, str] = {}
    for line in cpuinfo.splitlines():
        key, sep, value = line.partition(":")
        if not sep:
            if fields:
                break  # the first processor's block is enough
            continue
        fields.setdefault(key.strip(), value.strip())
    flags = set(fields.get("flags", "").split())
    return {
        "vendor": fields.get("vendor_id", "unknown"),
        "model": fields.get("model name", platform.processor() or "unknown"),
        # a hypervisor may show only "AMD EPYC": family and model tell the generation apart
        "family": f"{fields.get('cpu family', '?')}/{fields.get('model', '?')}",
        "isa": " ".join(f for f in ISA_FLAGS if f in flags) or "unknown",
    }


def describe() -> dict[str, object]:
    """This machine: its CPU, core count, architecture and numerical library versions."""
    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "absent"
    return {
        **cpu(),
        "cores": os.cpu_count() or 0,
        "arch": platform.machine(),
        "python": platform.python_version(),
        "libraries": versions,
    }


def label(machine: dict[str, object]) -> str:
    """One line naming a machine, for messages."""
    field = {k: machine.get(k, "?") for k in ("vendor", "model", "family", "isa", "arch")}
    return (
        f"{field['vendor']} {field['model']} (family/model {field['family']}, "
        f"{field['isa']}, {field['arch']})"
    )
