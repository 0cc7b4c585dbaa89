"""Who may connect to the live viewer's server (docs/viewer.md, its safety): a
token where one is set (always off loopback), the page's own origin and host
names only, and no path from a client to the file system."""

import urllib.error
import urllib.request

import aiohttp
import pytest

import mbao
from viewer_client import FRAME_TIMEOUT_S, run, served

SMALL = dict(width=48, height=40)


def test_a_token_guards_every_request_where_one_is_set():
    with served(**SMALL, token="t0k3n") as viewer:
        base = f"http://127.0.0.1:{viewer.port}/"
        for path in ("", "static/viewer.js"):
            with pytest.raises(urllib.error.HTTPError) as refused:
                urllib.request.urlopen(base + path, timeout=FRAME_TIMEOUT_S)
            assert refused.value.code == 403
        with urllib.request.urlopen(base + "?token=t0k3n", timeout=FRAME_TIMEOUT_S) as page:
            assert b'id="view"' in page.read()
            cookie = page.headers["Set-Cookie"].split(";")[0]
        request = urllib.request.Request(base + "static/viewer.js", headers={"Cookie": cookie})
        with urllib.request.urlopen(request, timeout=FRAME_TIMEOUT_S) as script:
            assert b"mbaoView" in script.read()

        async def socket_without_token():
            async with aiohttp.ClientSession() as http:
                with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
                    await http.ws_connect(base + "ws")
                return refused.value.status

        assert run(socket_without_token()) == 403


def test_a_host_other_than_loopback_gets_a_token_in_its_url():
    viewer = mbao.viewer.open_viewer(None, host="0.0.0.0", port=8750)  # not started: nothing binds
    assert viewer.token and viewer.url == f"http://0.0.0.0:8750/?token={viewer.token}"
    assert mbao.viewer.open_viewer(None, host="127.0.0.1").token is None


def test_websockets_from_another_origin_and_other_host_names_are_refused():
    with served(**SMALL) as viewer:
        base = f"http://127.0.0.1:{viewer.port}/"

        async def handshake(headers):
            async with aiohttp.ClientSession() as http:
                with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
                    await http.ws_connect(base + "ws", headers=headers)
                return refused.value.status

        assert run(handshake({"Origin": "http://example.com"})) == 403
        # A page of another site whose name was made to point at 127.0.0.1 (DNS rebinding).
        request = urllib.request.Request(base, headers={"Host": f"example.com:{viewer.port}"})
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(request, timeout=FRAME_TIMEOUT_S)
        assert refused.value.code == 403


@pytest.mark.parametrize(
    "path",
    [
        "static/..%2fserver.py",
        "static/%2e%2e/__init__.py",
        "static/viewer.py",
        "static/",
        "../../etc/passwd",
        "server.py",
    ],
)
def test_no_path_from_a_client_reaches_the_file_system(path):
    with served(**SMALL) as viewer:
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(f"http://127.0.0.1:{viewer.port}/{path}", timeout=FRAME_TIMEOUT_S)
        assert refused.value.code == 404
