"""vscan-load against a real vscand: the counts and percentiles of its report, the server's
memory read through the process found on the port, the catalogue left as it was, and refusals."""

import json
import os
import subprocess
import unittest

from harness import SOURCE_DIR, VSCAN, VSCAN_LOAD, Server

PLAN = os.path.join(SOURCE_DIR, "examples", "campaigns", "bunny_ur5.yaml")
KINDS = ("scan", "ik", "catalogue")


def vm_hwm_mib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    raise AssertionError("no VmHWM")


class BenchLoadTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # Four clients may start a scan the moment the last one ended, before the server has freed its
        # slot; eight slots keep such refusals out of a test that expects none.
        cls.server = Server(extra_args=["--max-concurrent-scans", "8"]).start()

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()

    def run_tool(self, tool, *args, server=None):
        return subprocess.run([tool, "--server", server or self.server.address, *args],
                              capture_output=True, text=True, timeout=240)

    def load(self, *args, server=None):
        return self.run_tool(VSCAN_LOAD, *args, server=server)

    def listed(self, kind):
        result = self.run_tool(VSCAN, "-q", kind, "list")
        self.assertEqual(result.returncode, 0, result.stderr)
        return result.stdout.split()

    def test_four_clients_report_adds_up(self):
        result = self.load("--json", PLAN, "--clients", "4", "--requests", "40",
                            "--width", "320", "--height", "240", "--seed", "3")
        self.assertEqual(result.returncode, 0, result.stderr)
        report = json.loads(result.stdout)
        self.assertEqual(report["clients"], 4)
        self.assertEqual(report["requests"], 40)
        self.assertEqual(report["ok"], 40)
        self.assertEqual(report["failed"], 0, report["errors"])
        self.assertEqual(report["errors"], {})
        kinds = report["kinds"]
        self.assertEqual(sum(kinds[k]["requests"] for k in KINDS), 40)
        self.assertEqual(sum(kinds[k]["latency"]["ok"] for k in KINDS), 40)
        # 40 draws from an even mix: each kind is drawn (the chance that one is not is below 1e-6).
        for kind in KINDS:
            latency = kinds[kind]["latency"]
            self.assertGreater(latency["ok"], 0, kind)
            self.assertGreater(latency["p50Ms"], 0, kind)
            self.assertLessEqual(latency["p50Ms"], latency["p99Ms"], kind)
            self.assertLessEqual(latency["p99Ms"], latency["maxMs"], kind)
        overall = report["latency"]
        self.assertLessEqual(overall["p50Ms"], overall["p99Ms"])
        self.assertEqual(overall["maxMs"], max(kinds[k]["latency"]["maxMs"] for k in KINDS))
        # elapsedS is printed to the millisecond, so the ratio agrees to about a percent on a short run.
        self.assertAlmostEqual(report["throughputPerS"] * report["elapsedS"] / 40, 1, delta=0.01)
        # Every scan looks at the bunny: some of its 320x240 rays hit it, never more than all of them.
        scans = kinds["scan"]["latency"]["ok"]
        self.assertGreater(report["scanPoints"], 0)
        self.assertLessEqual(report["scanPoints"], scans * 320 * 240)

        memory = report["serverMemory"]
        self.assertIsNotNone(memory, result.stderr)
        self.assertEqual(memory["pid"], self.server.process.pid)
        self.assertGreater(memory["samples"], 0)
        self.assertGreater(memory["startRssMib"], 0)
        self.assertLessEqual(memory["startRssMib"], memory["peakSampledRssMib"])
        self.assertLessEqual(memory["peakSampledRssMib"], memory["lifetimePeakRssMib"] + 0.05)
        self.assertLessEqual(memory["lifetimePeakRssMib"], vm_hwm_mib(self.server.process.pid) + 0.05)

        # What the run created is gone again.
        for kind in ("scene", "mesh", "robot"):
            self.assertEqual(self.listed(kind), [], kind)

    def test_localhost_and_text_report(self):
        result = self.load(PLAN, "--requests", "6", "--mix", "catalogue=1,ik=0",
                            server=f"localhost:{self.server.port}")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("6 calls ok, 0 failed", result.stdout)
        self.assertIn(f"server {self.server.process.pid} resident memory", result.stdout)

    def test_refuses_other_machines(self):
        for address in ("10.1.2.3:50051", "example.com:50051", "127.0.0.1.example.com:50051", "[::2]:50051",
                        "0.0.0.0:50051", "127.0.0.1"):
            result = self.load(PLAN, "--requests", "1", server=address)
            self.assertEqual(result.returncode, 2, address)
            self.assertIn("--server", result.stderr, address)

    def test_refuses_bad_mix_and_bounds(self):
        for args in (["--mix", "scan=1,upload=2"], ["--mix", "scan=0"], ["--clients", "65"],
                     ["--duration", "601"], ["--mix", "scan=-1,ik=1"]):
            result = self.load(PLAN, *args)
            self.assertEqual(result.returncode, 2, args)

    def test_vscan_has_no_bench_command(self):
        # The load generator is vscan-load alone; `vscan bench load` is a usage error, run nothing.
        result = self.run_tool(VSCAN, "bench", "load", PLAN, "--requests", "1")
        self.assertEqual(result.returncode, 2, result.stdout)
        self.assertEqual(result.stdout, "")
        self.assertEqual(self.listed("scene"), [])


if __name__ == "__main__":
    unittest.main()
