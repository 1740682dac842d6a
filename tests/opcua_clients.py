#!/usr/bin/env python3
"""What an independent OPC UA client (Python asyncua) meets when it connects
to `addipos serve --opcua` the way users do (`.ci/run` runs this after
`cargo test`):

    python3 tests/opcua_clients.py target/debug/addipos

1. Endpoints for the names users type: GetEndpoints asked with
   `opc.tcp://localhost:PORT/`, `opc.tcp://localhost:PORT` (no slash), this
   machine's name and the listen address each finds an endpoint whose URL
   is the one asked with (what node-opcua's `endpointMustExist` checks),
   and a session opens with each URL.
2. Event items get events only: a monitored item on the tool list's and on
   the Server object's EventNotifier gets the tool list's model change and
   no data change (no first DataChangeNotification with
   BadWaitingForInitialData).
3. The guarded endpoint (`--allow-remote`) refuses an anonymous user with
   the status docs/opcua.md names, `BadIdentityTokenInvalid`.
4. The server's certificate has the subject of the settings (no library
   defaults) and names each host once.

Exit status 0 when every check holds; a failed check raises.
"""

import asyncio
import datetime
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from asyncua import Client, ua
from asyncua.crypto.security_policies import SecurityPolicyBasic256Sha256
from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import rsa
from cryptography.x509.oid import NameOID

ROOT = Path(__file__).resolve().parent.parent
MACHINE_TOOL = "http://opcfoundation.org/UA/MachineTool/"
# Bounds every wait for the server (start, an event).
WAIT_S = 30.0


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    """`addipos serve --opcua` on free ports, stopped on exit."""

    def __init__(self, exe, data_dir, *args):
        self.exe = exe
        self.data_dir = data_dir
        self.uoi = f"127.0.0.1:{free_port()}"
        self.port = free_port()
        self.proc = subprocess.Popen(
            [exe, "serve", "--no-persist", "--data-dir", data_dir,
             "--listen", self.uoi, "--opcua", f"127.0.0.1:{self.port}", *args],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def url(self, host="127.0.0.1", slash="/"):
        return f"opc.tcp://{host}:{self.port}{slash}"

    def call(self, *request):
        out = subprocess.run([self.exe, "call", self.uoi, *request],
                             capture_output=True, text=True, timeout=60)
        return out.stdout.strip() or out.stderr.strip()

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()


async def started(client):
    """Connects `client`; the server may still be starting."""
    deadline = time.monotonic() + WAIT_S
    while True:
        try:
            await client.connect()
            return client
        except (OSError, asyncio.TimeoutError):
            if time.monotonic() > deadline:
                raise
            await asyncio.sleep(0.2)


async def endpoints_for_the_names_users_type(server):
    first = await started(Client(server.url()))
    await first.disconnect()
    hosts = ["localhost", "127.0.0.1", socket.gethostname()]
    for host in hosts:
        for slash in ("/", ""):
            url = server.url(host, slash)
            client = Client(url)
            described = [e.EndpointUrl for e in await client.connect_and_get_server_endpoints()]
            # Exactly the URL asked with, as node-opcua compares it (a
            # string, the trailing slash included), and first.
            assert described[0] == url, (url, described)
            client = Client(url)
            await client.connect()
            await client.disconnect()
    print(f"endpoints: a session with each of {hosts}, with and without the trailing slash")


class EventsOnly:
    """Counts events and data changes."""

    def __init__(self):
        self.events = []
        self.data_changes = []
        self.arrived = asyncio.Event()

    def datachange_notification(self, node, value, data):
        self.data_changes.append((node, value, data.monitored_item.Value.StatusCode))

    def event_notification(self, event):
        self.events.append(event)
        self.arrived.set()


async def event_items_get_events_only(server):
    client = await started(Client(server.url()))
    try:
        mt = await client.get_namespace_index(MACHINE_TOOL)
        tools = await tool_list(client, mt)
        handler = EventsOnly()
        sub = await client.create_subscription(20, handler)
        await sub.subscribe_events(tools, ua.ObjectIds.GeneralModelChangeEventType,
                                   where_clause_generation=False)
        await sub.subscribe_events(client.nodes.server, ua.ObjectIds.BaseEventType,
                                   where_clause_generation=False)
        # A new tool raises a model change from the tool list, which the
        # Server object's subscriber gets too.
        assert server.call("W", "1300/1/3/8", "i", "4") == "ok"
        assert server.call("W", "1300/1/3/6", "d", "1.5") == "ok"
        deadline = time.monotonic() + WAIT_S
        while len(handler.events) < 2:
            handler.arrived.clear()
            await asyncio.wait_for(handler.arrived.wait(), max(deadline - time.monotonic(), 0.01))
        assert not handler.data_changes, handler.data_changes
        await sub.delete()
    finally:
        await client.disconnect()
    print(f"event items: {len(handler.events)} events, no data change")


async def tool_list(client, mt):
    """Objects/Machines/<the machine>/Equipment/Tools, found by browsing."""
    objects = client.nodes.objects
    for machines in await objects.get_children():
        name = await machines.read_browse_name()
        if name.Name != "Machines":
            continue
        for machine in await machines.get_children():
            equipment = await machine.get_child(f"{mt}:Equipment")
            return await equipment.get_child(f"{mt}:Tools")
    raise AssertionError("no machine under Objects/Machines")


def client_certificate(folder):
    """A self-signed client certificate and key (DER, PEM) in `folder`."""
    key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "opcua_clients.py")])
    uri = "urn:addipos-tc:test-client"
    cert = (x509.CertificateBuilder()
            .subject_name(name).issuer_name(name)
            .public_key(key.public_key())
            .serial_number(x509.random_serial_number())
            .not_valid_before(datetime.datetime(2020, 1, 1))
            .not_valid_after(datetime.datetime(2099, 1, 1))
            .add_extension(x509.SubjectAlternativeName(
                [x509.UniformResourceIdentifier(uri), x509.DNSName("localhost"),
                 x509.DNSName(socket.gethostname())]), False)
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), True)
            .add_extension(x509.KeyUsage(True, True, True, True, False, False, False,
                                         False, False), True)
            .add_extension(x509.ExtendedKeyUsage(
                [x509.oid.ExtendedKeyUsageOID.CLIENT_AUTH,
                 x509.oid.ExtendedKeyUsageOID.SERVER_AUTH]), False)
            .sign(key, hashes.SHA256()))
    cert_path, key_path = Path(folder) / "client.der", Path(folder) / "client.pem"
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.DER))
    key_path.write_bytes(key.private_bytes(serialization.Encoding.PEM,
                                           serialization.PrivateFormat.TraditionalOpenSSL,
                                           serialization.NoEncryption()))
    return uri, str(cert_path), str(key_path)


async def anonymous_on_the_guarded_endpoint(server, work):
    uri, cert, key = client_certificate(work)
    deadline = time.monotonic() + WAIT_S
    while True:
        client = Client(server.url())
        client.application_uri = uri
        try:
            # Asks the server for its endpoints: it may still be starting.
            await client.set_security(SecurityPolicyBasic256Sha256, cert, key,
                                      mode=ua.MessageSecurityMode.SignAndEncrypt)
            await client.connect()
        except ua.UaStatusCodeError as e:
            status = e.code
            break
        except (OSError, asyncio.TimeoutError):
            if time.monotonic() > deadline:
                raise
            await asyncio.sleep(0.2)
            continue
        await client.disconnect()
        raise AssertionError("an anonymous user was let in")
    assert status == ua.StatusCodes.BadIdentityTokenInvalid, ua.StatusCode(status)
    print("guarded endpoint: anonymous user refused with BadIdentityTokenInvalid")


def certificate_names_each_host_once(server):
    der = (Path(server.data_dir) / "opcua/own/cert.der").read_bytes()
    cert = x509.load_der_x509_certificate(der)
    subject = {a.oid._name: a.value for a in cert.subject}
    assert subject.get("commonName") == "addipos TC emulator", subject
    assert subject.get("organizationName") == "addipos-tc", subject
    assert "stateOrProvinceName" not in subject and "countryName" not in subject, subject
    san = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    names = [str(n.value) for n in san]
    assert len(names) == len(set(n.lower() for n in names)), names
    for host in ("localhost", "127.0.0.1", socket.gethostname()):
        assert host in names, (host, names)
    print(f"certificate: {cert.subject.rfc4514_string()}, {len(names)} distinct names")


async def check(exe):
    with tempfile.TemporaryDirectory() as work:
        server = Server(exe, os.path.join(work, "open"))
        try:
            await endpoints_for_the_names_users_type(server)
            await event_items_get_events_only(server)
            certificate_names_each_host_once(server)
        finally:
            server.stop()
        server = Server(exe, os.path.join(work, "guarded"), "--allow-remote")
        try:
            await anonymous_on_the_guarded_endpoint(server, work)
        finally:
            server.stop()


if __name__ == "__main__":
    asyncio.run(check(sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "target/debug/addipos")))
    print("ok: endpoints, event items, the guarded login and the certificate as clients see them")
