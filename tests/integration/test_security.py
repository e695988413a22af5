"""TLS, mutual TLS and bearer tokens against a real vscand, through the CLI (the C++ client library)
and the Python client, with certificates made by scripts/make-test-certs.sh."""

import json
import os
import subprocess
import tempfile
import unittest

import grpc

from harness import SOURCE_DIR, VSCAN, Server

from vscan import Client, VscanError

TOKEN = "s3cret-Token_0123"
CALL_SECONDS = "5"

_tmp = None
CERTS = None  # the CA vscand trusts, its server certificate and a client certificate
OTHER = None  # an unrelated CA with its own client certificate


def setUpModule():
    global _tmp, CERTS, OTHER
    _tmp = tempfile.TemporaryDirectory(prefix="vscan-certs-")
    CERTS = os.path.join(_tmp.name, "lab")
    OTHER = os.path.join(_tmp.name, "other")
    for directory in (CERTS, OTHER):
        subprocess.run([os.path.join(SOURCE_DIR, "scripts", "make-test-certs.sh"), directory], check=True,
                       capture_output=True, timeout=60)


def tearDownModule():
    _tmp.cleanup()


def cert(name, directory=None):
    return os.path.join(directory or CERTS, name)


def tls_args(mutual=False):
    args = ["--tls-cert", cert("server.crt"), "--tls-key", cert("server.key")]
    return args + (["--tls-client-ca", cert("ca.crt")] if mutual else [])


class SecureServerCase(unittest.TestCase):
    """One vscand per class started with server_args(); vscan() runs the CLI against it."""

    @classmethod
    def server_args(cls):
        return []

    @classmethod
    def setUpClass(cls):
        cls.server = Server(extra_args=cls.server_args()).start()

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()

    def vscan(self, *args, env=None):
        return subprocess.run([VSCAN, "--server", self.server.address, "--timeout", CALL_SECONDS, "--json", *args],
                              capture_output=True, text=True, timeout=60,
                              env={**os.environ, **(env or {})})

    def assertCliWorks(self, *options, env=None):
        health = self.vscan(*options, "health", env=env)
        self.assertEqual(health.returncode, 0, health.stderr)
        self.assertEqual(json.loads(health.stdout)["status"], "SERVING")
        created = self.vscan(*options, "scene", "create", "secured", env=env)
        self.assertEqual(created.returncode, 0, created.stderr)
        scene_id = json.loads(created.stdout)["sceneId"]
        listed = self.vscan(*options, "scene", "list", env=env)
        self.assertEqual(listed.returncode, 0, listed.stderr)
        self.assertIn(scene_id, listed.stdout)

    def assertCliFails(self, code, *args):
        result = self.vscan(*args)
        self.assertEqual(result.returncode, 4 if code == "UNAVAILABLE" else 3, result.stderr)
        self.assertEqual(json.loads(result.stdout.splitlines()[-1])["error"]["code"], code, result.stdout)

    def assertPythonWorks(self, **options):
        with Client(self.server.address, timeout=float(CALL_SECONDS), **options) as client:
            self.assertEqual(client.health(), "SERVING")
            scene = client.create_scene("secured-py")
            self.assertIn(scene.scene_id, [s.scene_id for s in client.list_scenes()])

    def assertPythonFails(self, code, call="list_scenes", **options):
        with Client(self.server.address, timeout=float(CALL_SECONDS), **options) as client:
            with self.assertRaises(VscanError) as ctx:
                getattr(client, call)()
            self.assertEqual(ctx.exception.code, code, ctx.exception.message)


class TlsTest(SecureServerCase):
    """--tls-cert/--tls-key: clients must trust the CA that signed the server's certificate."""

    @classmethod
    def server_args(cls):
        return tls_args()

    def test_cli_with_the_ca_works(self):
        self.assertCliWorks("--ca-cert", cert("ca.crt"))
        self.assertCliWorks(env={"VSCAN_CA_CERT": cert("ca.crt")})

    def test_cli_without_the_ca_fails(self):
        self.assertCliFails("UNAVAILABLE", "health")  # plaintext against a TLS port
        self.assertCliFails("UNAVAILABLE", "--tls", "health")  # the default roots do not hold the test CA
        self.assertCliFails("UNAVAILABLE", "--ca-cert", cert("ca.crt", OTHER), "health")
        self.assertCliFails("UNAVAILABLE", "--ca-cert", cert("ca.crt", OTHER), "scene", "list")

    def test_cli_refuses_half_a_client_certificate(self):
        result = self.vscan("--ca-cert", cert("ca.crt"), "--client-cert", cert("client.crt"), "health")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("--client-key", result.stderr)

    def test_python_with_the_ca_works(self):
        self.assertPythonWorks(root_cert=cert("ca.crt"))

    def test_python_without_the_ca_fails(self):
        self.assertPythonFails(grpc.StatusCode.UNAVAILABLE, call="health")
        self.assertPythonFails(grpc.StatusCode.UNAVAILABLE, call="health", tls=True)
        self.assertPythonFails(grpc.StatusCode.UNAVAILABLE, root_cert=cert("ca.crt", OTHER))

    def test_python_refuses_half_a_client_certificate(self):
        with self.assertRaises(ValueError):
            Client(self.server.address, root_cert=cert("ca.crt"), client_cert=cert("client.crt"))


class MutualTlsTest(SecureServerCase):
    """--tls-client-ca as well: only clients with a certificate that CA signed get through."""

    @classmethod
    def server_args(cls):
        return tls_args(mutual=True)

    def client_cert_args(self, directory=None):
        return ["--client-cert", cert("client.crt", directory), "--client-key", cert("client.key", directory)]

    def test_cli_with_a_client_certificate_works(self):
        self.assertCliWorks("--ca-cert", cert("ca.crt"), *self.client_cert_args())
        self.assertCliWorks(env={"VSCAN_CA_CERT": cert("ca.crt"), "VSCAN_CLIENT_CERT": cert("client.crt"),
                                 "VSCAN_CLIENT_KEY": cert("client.key")})

    def test_cli_without_a_client_certificate_fails(self):
        self.assertCliFails("UNAVAILABLE", "--ca-cert", cert("ca.crt"), "health")
        self.assertCliFails("UNAVAILABLE", "--ca-cert", cert("ca.crt"), "scene", "list")

    def test_cli_with_a_certificate_from_another_ca_fails(self):
        self.assertCliFails("UNAVAILABLE", "--ca-cert", cert("ca.crt"), *self.client_cert_args(OTHER), "scene", "list")

    def test_python_with_a_client_certificate_works(self):
        self.assertPythonWorks(root_cert=cert("ca.crt"), client_cert=cert("client.crt"),
                               client_key=cert("client.key"))

    def test_python_without_a_client_certificate_fails(self):
        self.assertPythonFails(grpc.StatusCode.UNAVAILABLE, call="health", root_cert=cert("ca.crt"))
        self.assertPythonFails(grpc.StatusCode.UNAVAILABLE, root_cert=cert("ca.crt"),
                               client_cert=cert("client.crt", OTHER), client_key=cert("client.key", OTHER))


class TokenServerCase(SecureServerCase):
    """A server that reads TOKEN from a --token-file written before it starts."""

    token_line_end = "\n"

    @classmethod
    def setUpClass(cls):
        cls.token_dir = tempfile.TemporaryDirectory(prefix="vscan-token-")
        cls.token_file = os.path.join(cls.token_dir.name, "token")
        with open(cls.token_file, "w") as f:
            f.write(TOKEN + cls.token_line_end)
        super().setUpClass()

    @classmethod
    def tearDownClass(cls):
        super().tearDownClass()
        cls.token_dir.cleanup()


class TokenTest(TokenServerCase):
    """--token-file over plaintext: every call but the health check needs the bearer token."""

    token_line_end = "\r\n"  # a line ending from another system is not part of the token

    @classmethod
    def server_args(cls):
        return ["--token-file", cls.token_file]

    def test_cli_health_needs_no_token(self):
        result = self.vscan("health")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(json.loads(result.stdout)["status"], "SERVING")

    def test_cli_without_or_with_a_wrong_token_is_unauthenticated(self):
        self.assertCliFails("UNAUTHENTICATED", "scene", "list")
        # Shorter, longer, one character off, and the right token with different case.
        for wrong in (TOKEN[:-1], TOKEN + "4", TOKEN[:-1] + "4", TOKEN.upper(), "x"):
            self.assertCliFails("UNAUTHENTICATED", "--token", wrong, "scene", "list")

    def test_cli_with_the_token_works(self):
        self.assertCliWorks("--token", TOKEN)
        self.assertCliWorks(env={"VSCAN_TOKEN": TOKEN})

    def test_python_health_needs_no_token(self):
        with Client(self.server.address, timeout=float(CALL_SECONDS)) as client:
            self.assertEqual(client.health(), "SERVING")

    def test_python_without_or_with_a_wrong_token_is_unauthenticated(self):
        self.assertPythonFails(grpc.StatusCode.UNAUTHENTICATED)
        for wrong in (TOKEN[:-1], TOKEN + "4", TOKEN.upper()):
            self.assertPythonFails(grpc.StatusCode.UNAUTHENTICATED, token=wrong)

    def test_python_with_the_token_works(self):
        self.assertPythonWorks(token=TOKEN)


class MutualTlsWithTokenTest(TokenServerCase):
    """A lab's full setup: mutual TLS and a token. Each check stands on its own."""


    @classmethod
    def server_args(cls):
        return tls_args(mutual=True) + ["--token-file", cls.token_file]

    def secure(self):
        return ["--ca-cert", cert("ca.crt"), "--client-cert", cert("client.crt"), "--client-key", cert("client.key")]

    def test_certificate_and_token_work(self):
        self.assertCliWorks(*self.secure(), "--token", TOKEN)
        self.assertPythonWorks(root_cert=cert("ca.crt"), client_cert=cert("client.crt"),
                               client_key=cert("client.key"), token=TOKEN)

    def test_certificate_without_the_token_is_unauthenticated(self):
        self.assertCliFails("UNAUTHENTICATED", *self.secure(), "scene", "list")
        self.assertCliFails("UNAUTHENTICATED", *self.secure(), "--token", "wrong", "scene", "list")
        health = self.vscan(*self.secure(), "health")
        self.assertEqual(health.returncode, 0, health.stderr)

    def test_token_without_a_certificate_fails(self):
        self.assertCliFails("UNAVAILABLE", "--ca-cert", cert("ca.crt"), "--token", TOKEN, "scene", "list")


class ServerRefusesHalfConfigurationsTest(unittest.TestCase):
    def run_vscand(self, *args):
        with tempfile.TemporaryDirectory(prefix="vscand-refuse-") as data:
            server = Server(data_dir=data, extra_args=args)
            with self.assertRaises(RuntimeError) as ctx:
                server.start()
            server.stop()
            return str(ctx.exception)

    def test_client_ca_without_a_server_certificate(self):
        self.assertIn("--tls-client-ca", self.run_vscand("--tls-client-ca", cert("ca.crt")))

    def test_token_file_with_a_space(self):
        with tempfile.NamedTemporaryFile("w", suffix=".token") as f:
            f.write("two words\n")
            f.flush()
            self.assertIn("--token-file", self.run_vscand("--token-file", f.name))


if __name__ == "__main__":
    unittest.main()
