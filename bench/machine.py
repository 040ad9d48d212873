"""The machine a bench table was measured on, for the tables' provenance line.

Cloud machines of one product name differ: "AMD EPYC" has been both a Zen 3 and
a Zen 4 here, and the 1.66M skinning pass runs about 1.7x faster on the second.
The line therefore names the CPU family and model numbers and the widest SIMD
the CPU offers next to the model name.
"""
import os
import platform
import re
import subprocess


def describe():
    """'AMD EPYC (family 25, model 17, AVX-512), 2 logical cores' and the like."""
    try:
        text = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    except OSError:
        text = ""

    def field(name):
        match = re.search(r"^%s:\s*(.*)$" % re.escape(name), text, re.MULTILINE)
        return match.group(1).strip() if match else ""

    model = field("Model name") or platform.processor() or "unknown CPU"
    flags = field("Flags").split()
    simd = ("AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags
            else "no AVX2" if flags else "")
    details = ["family %s" % field("CPU family")] if field("CPU family") else []
    if field("Model"):
        details.append("model %s" % field("Model"))
    if simd:
        details.append(simd)
    suffix = " (%s)" % ", ".join(details) if details else ""
    return "%s%s, %d logical cores" % (model, suffix, os.cpu_count())


if __name__ == "__main__":
    print(describe())
