"""What the web view's tests share: a vscand web listener with a token, HTTP requests to it, and the
page scripts in tests/integration/web/ run in headless chromium."""

import http.client
import json
import os
import shutil
import socket
import subprocess
import tempfile

from harness import SOURCE_DIR, ServerTestCase

CHROMIUM = "/usr/bin/chromium"
PUPPETEER = os.path.join(SOURCE_DIR, ".tools", "node_modules", "puppeteer-core")
PAGE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "web")
# The page's background colour (web/common.js).
BACKGROUND = (0x20, 0x20, 0x20)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def web_listen(directory, token):
    """Writes TOKEN to a token file in DIRECTORY and picks a free port for the web view:
    (port, "127.0.0.1:PORT", the vscand arguments --token-file FILE --web-listen ADDRESS)."""
    token_file = os.path.join(directory, "token")
    with open(token_file, "w") as f:
        f.write(token + "\n")
    port = free_port()
    address = f"127.0.0.1:{port}"
    return port, address, ("--token-file", token_file, "--web-listen", address)


def http_get(address, path, token=None, method="GET", timeout=10):
    """(status, content type, body) of one request to the web view at ADDRESS, its path sent as it is,
    with the bearer TOKEN unless it is None."""
    connection = http.client.HTTPConnection(address, timeout=timeout)
    try:
        headers = {} if token is None else {"Authorization": f"Bearer {token}"}
        connection.request(method, path, headers=headers)
        response = connection.getresponse()
        return response.status, response.getheader("Content-Type"), response.read()
    finally:
        connection.close()


class WebServerTestCase(ServerTestCase):
    """A ServerTestCase whose vscand serves the web view too, at cls.web (port cls.web_port), with the
    bearer token cls.token; cls.tmp (removed after the class) holds the token file."""

    token = None

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-web-")
        cls.web_port, cls.web, cls.server_args = web_listen(cls.tmp.name, cls.token)
        super().setUpClass()

    @classmethod
    def tearDownClass(cls):
        super().tearDownClass()
        cls.tmp.cleanup()


def need_browser(test):
    """Skips TEST unless chromium, puppeteer-core and node are installed."""
    if not os.access(CHROMIUM, os.X_OK):
        test.skipTest(f"{CHROMIUM} is not installed (Debian package chromium; scripts/install-deps.sh)")
    if not os.path.isdir(PUPPETEER):
        test.skipTest("puppeteer-core is not in .tools/ (scripts/install-deps.sh)")
    if not shutil.which("node"):
        test.skipTest("node is not installed")


def page_command(script, *args):
    """The command line that runs page script SCRIPT (a name in tests/integration/web/) with ARGS."""
    return ["node", os.path.join(PAGE_DIR, script), PUPPETEER, CHROMIUM, *args]


def run_page(test, script, *args, timeout=240):
    """Runs page script SCRIPT with ARGS (skipping TEST without a browser); its last line of output,
    parsed as JSON."""
    need_browser(test)
    run = subprocess.run(page_command(script, *args), capture_output=True, text=True, timeout=timeout)
    test.assertEqual(run.returncode, 0, run.stdout + run.stderr)
    return json.loads(run.stdout.strip().splitlines()[-1])
