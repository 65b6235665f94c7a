"""The machine description names the CPU by vendor, model, family and instruction-set levels."""

from ftfof.pipeline import machine

CPUINFO = """processor\t: 0
vendor_id\t: GenuineIntel
cpu family\t: 6
model\t\t: 143
model name\t: Intel(R) Xeon(R) Platinum 8480+
flags\t\t: fpu sse2 avx fma avx2 avx512f avx512bw

processor\t: 1
vendor_id\t: SomethingElse
model name\t: not read
"""


def test_cpu_reads_the_first_processor_block():
    assert machine.cpu(CPUINFO) == {
        "vendor": "GenuineIntel",
        "model": "Intel(R) Xeon(R) Platinum 8480+",
        "family": "6/143",
        "isa": "fma avx2 avx512f",
    }


def test_a_machine_without_cpuinfo_is_described_as_unknown_not_refused():
    described = machine.cpu("")
    assert described["vendor"] == "unknown" and described["isa"] == "unknown"


def test_describe_names_the_libraries_that_decide_the_bits():
    described = machine.describe()
    assert set(machine.LIBRARIES) <= described["libraries"].keys()
    assert described["cores"] >= 1
    label = machine.label(described)
    assert str(described["vendor"]) in label and str(described["family"]) in label
