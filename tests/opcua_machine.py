#!/usr/bin/env python3
"""The machine of `addipos serve --opcua` as an independent client sees it
(Python asyncua; `.ci/run` runs this after `cargo test`).

    python3 tests/opcua_machine.py target/debug/addipos

It starts a server of its own (temporary data directory, free ports) and
checks, following OPC 40501-1 and docs/opcua.md only:

1. the machine is found from Objects by its type, MachineToolType of the
   namespace http://opcfoundation.org/UA/MachineTool/ (index looked up in
   the NamespaceArray, never assumed), and its Identification is read;
2. the tool list is listed; a UOI write of a new tool's radius makes the
   tool appear, announced by a GeneralModelChangeEvent, with that radius
   and its identifiers;
3. the general OTC example (tests/nc/otc_general.nc with docs/nc/disc.wz)
   is run on the served emulator: `addipos run --trace` records its
   requests on a fresh emulator, and each one is sent to the server with
   `addipos call`, its answer checked against the recorded one; the tool's
   ToolLife then shows the booked wear.

Exit status 0 when every check holds; a failed check raises.
"""

import asyncio
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from asyncua import Client, ua

MACHINE_TOOL = "http://opcfoundation.org/UA/MachineTool/"
DI = "http://opcfoundation.org/UA/DI/"
OWN = "urn:addipos-tc"
ROOT = Path(__file__).resolve().parent.parent
# How long a change may take to show (the face polls every 100 ms).
SHOW_WITHIN_S = 5.0


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    """`addipos serve --opcua` on free ports, stopped on exit."""

    def __init__(self, exe, data_dir):
        self.exe = exe
        self.uoi = f"127.0.0.1:{free_port()}"
        self.opcua_port = free_port()
        self.proc = subprocess.Popen(
            [exe, "serve", "--no-persist", "--data-dir", data_dir,
             "--listen", self.uoi, "--opcua", f"127.0.0.1:{self.opcua_port}"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)

    def url(self):
        return f"opc.tcp://127.0.0.1:{self.opcua_port}/"

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


async def connect(url):
    """A connected client; the server may still be starting."""
    deadline = time.monotonic() + 60
    while True:
        client = Client(url)
        try:
            await client.connect()
            return client
        except (OSError, asyncio.TimeoutError, ua.UaError):
            if time.monotonic() > deadline:
                raise
            await asyncio.sleep(0.2)


async def find_machines(client, machine_tool_type):
    """Objects of MachineToolType (or a subtype) up to two levels below
    Objects (Machinery puts machines in Objects/Machines)."""
    found = []
    level = [client.nodes.objects]
    for _ in range(2):
        below = []
        for node in level:
            for ref in await node.get_references(
                    refs=ua.ObjectIds.HierarchicalReferences,
                    direction=ua.BrowseDirection.Forward,
                    nodeclassmask=ua.NodeClass.Object):
                child = client.get_node(ref.NodeId)
                if await is_of_type(client, ref.TypeDefinition, machine_tool_type):
                    found.append(child)
                below.append(child)
        level = below
    return found


async def is_of_type(client, type_id, wanted):
    """Whether `type_id` is `wanted` or one of its subtypes."""
    at = type_id
    for _ in range(32):
        if at == wanted:
            return True
        if at.NamespaceIndex == 0 and at.Identifier in (58, 63):
            return False
        supers = await client.get_node(at).get_references(
            refs=ua.ObjectIds.HasSubtype, direction=ua.BrowseDirection.Inverse)
        if not supers:
            return False
        at = supers[0].NodeId
    return False


async def child(node, ns, name):
    return await node.get_child(f"{ns}:{name}")


async def tools_of(client, tool_list, mt):
    """The tools in the list: {(group, number): node}."""
    tool_type = ua.NodeId(50, mt)
    out = {}
    for ref in await tool_list.get_references(
            refs=ua.ObjectIds.HierarchicalReferences,
            direction=ua.BrowseDirection.Forward,
            nodeclassmask=ua.NodeClass.Object):
        if not await is_of_type(client, ref.TypeDefinition, tool_type):
            continue
        tool = client.get_node(ref.NodeId)
        number = await (await child(tool, mt, "ControlIdentifier1")).read_value()
        group = await (await child(tool, mt, "ControlIdentifier2")).read_value()
        out[(group, number)] = tool
    return out


class ModelChanges:
    """Collects GeneralModelChangeEvents."""

    def __init__(self):
        self.changes = []
        self.arrived = asyncio.Event()

    def datachange_notification(self, node, value, data):
        pass

    def event_notification(self, event):
        if event.EventType == ua.NodeId(ua.ObjectIds.GeneralModelChangeEventType):
            self.changes.extend(event.Changes or [])
            self.arrived.set()


async def until(check, what):
    deadline = time.monotonic() + SHOW_WITHIN_S
    while True:
        value = await check()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"not within {SHOW_WITHIN_S} s: {what}")
        await asyncio.sleep(0.05)


async def identification(client, machine):
    di = await client.get_namespace_index(DI)
    ident = await child(machine, di, "Identification")
    values = {}
    for name in ("Manufacturer", "Model", "SerialNumber", "SoftwareRevision",
                 "ProductInstanceUri"):
        values[name] = await (await child(ident, di, name)).read_value()
    assert values["Manufacturer"].Text == "addipos-tc", values
    assert values["SerialNumber"] == "1", values
    assert values["ProductInstanceUri"] == "urn:addipos-tc:machine:1", values
    assert values["SoftwareRevision"], values
    print("identification:", {k: getattr(v, "Text", v) for k, v in values.items()})


async def new_tool_appears(client, server, tool_list, mt):
    before = await tools_of(client, tool_list, mt)
    assert (2, 5) not in before, before
    version = await (await tool_list.get_child("0:NodeVersion")).read_value()
    handler = ModelChanges()
    sub = await client.create_subscription(50, handler)
    # The fields of GeneralModelChangeEventType (Changes among them),
    # without asyncua's `EventType InList [...]` where clause: the server
    # evaluates OfType but not InList over NodeIds (docs/opcua.md); the
    # tool list raises model changes only.
    await sub.subscribe_events(tool_list, ua.ObjectIds.GeneralModelChangeEventType,
                               where_clause_generation=False)
    assert server.call("W", "1300/1/2/8", "i", "5") == "ok"
    assert server.call("W", "1300/1/2/6", "d", "2.5") == "ok"
    await asyncio.wait_for(handler.arrived.wait(), SHOW_WITHIN_S)
    tool_type = ua.NodeId(50, mt)
    added = [c for c in handler.changes if c.AffectedType == tool_type and c.Verb & 1]
    assert added, handler.changes
    tools = await tools_of(client, tool_list, mt)
    tool = tools[(2, 5)]
    assert tool.nodeid == added[0].Affected, (tool.nodeid, added)
    own = await client.get_namespace_index(OWN)
    radius = await (await tool.get_child(f"{own}:Radius")).read_value()
    assert radius == 2.5, radius
    name = await (await child(tool, mt, "Name")).read_value()
    interpretation = await (await child(tool, mt, "ControlIdentifierInterpretation")).read_value()
    locked = await (await child(tool, mt, "Locked")).read_value()
    assert (name, interpretation, locked) == ("G2 T5", 1, False), (name, interpretation, locked)
    after = await (await tool_list.get_child("0:NodeVersion")).read_value()
    assert after != version, (version, after)
    print(f"new tool: {name} radius {radius}, NodeVersion {version} -> {after}, "
          f"{len(handler.changes)} change(s) in the event")


def trace_requests(exe, work):
    """The requests of the general OTC example and their answers, as
    `addipos run` records them on a fresh emulator."""
    trace = Path(work) / "otc.trace"
    subprocess.run([exe, "run", str(ROOT / "tests/nc/otc_general.nc"),
                    "--tools", str(ROOT / "docs/nc/disc.wz"), "--trace", str(trace)],
                   check=True, capture_output=True, text=True)
    steps = []
    for line in trace.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line or line.startswith(("@", "<")):
            continue
        request, answer = (part.strip() for part in line.split("=>", 1))
        steps.append((request.split(), answer))
    return steps


async def otc_run_books_wear(client, server, tool_list, mt, work):
    steps = trace_requests(server.exe, work)
    booked = None
    for request, answer in steps:
        got = server.call(*request)
        assert got == answer or _same_number(got, answer), (request, answer, got)
        if request[:2] == ["R", "1300/3/1/10"]:
            booked = float(answer)
    assert booked and booked > 0, booked
    own = await client.get_namespace_index(OWN)
    wear_path = [f"{mt}:ToolLife", f"{own}:WearRadius"]

    async def tool_life():
        tools = await tools_of(client, tool_list, mt)
        if (1, 1) not in tools:
            return None
        wear = await (await tools[(1, 1)].get_child(wear_path)).read_value()
        return (tools[(1, 1)], wear) if wear == booked else None
    tool, wear = await until(tool_life, f"G1 T1 ToolLife/WearRadius = {booked}")
    entry = await tool.get_child(wear_path)
    unit = await (await entry.get_child(f"{mt}:EngineeringUnits")).read_value()
    assert unit.DisplayName.Text == "mm", unit
    radius = await (await tool.get_child(f"{own}:Radius")).read_value()
    # The figures docs/opcua.md gives, exactly: the wear is booked to
    # 1e-10 mm, without the noise of summing it cycle by cycle.
    assert (wear, radius) == (9.5, 20.5), (wear, radius)
    print(f"OTC run: {len(steps)} requests sent; G1 T1 WearRadius {wear} mm, radius {radius} mm")


def _same_number(got, want):
    try:
        return float(got) == float(want)
    except ValueError:
        return False


async def check(exe):
    with tempfile.TemporaryDirectory() as work:
        server = Server(exe, os.path.join(work, "data"))
        try:
            client = await connect(server.url())
            try:
                mt = await client.get_namespace_index(MACHINE_TOOL)
                machines = await find_machines(client, ua.NodeId(13, mt))
                assert len(machines) == 1, machines
                machine = machines[0]
                print("machine:", machine.nodeid.to_string(), "(MachineToolType, ns", mt, ")")
                await identification(client, machine)
                tool_list = await child(await child(machine, mt, "Equipment"), mt, "Tools")
                print("tools at start:", sorted(await tools_of(client, tool_list, mt)))
                await new_tool_appears(client, server, tool_list, mt)
                await otc_run_books_wear(client, server, tool_list, mt, work)
            finally:
                await client.disconnect()
        finally:
            server.stop()


if __name__ == "__main__":
    asyncio.run(check(sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "target/debug/addipos")))
    print("ok: the machine, its tools and their wear as OPC 40501-1 models them")
