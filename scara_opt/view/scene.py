"""A meshcat scene recorded in this process and written as meshcat's own static HTML.

meshcat's ``Visualizer.static_html()`` asks its ZMQ server for the scene: the server keeps
every drawing command in a tree (one object, transform, property list and animation per
path) and packs them, base64-encoded, into one HTML page with ``main.min.js`` inlined.
:class:`RecordingWindow` stands in for the server's window: it keeps the same tree from
the same commands (msgpack-encoded as meshcat sends them) and :func:`static_html` writes the
page the same way, through meshcat's ``create_command``, with no server, port or socket.
scara_opt's own part of the page (``page.js``, ``page.css``: the camera fitted to the window,
the labels and the control bar) is inlined after it, with its data as JSON.
"""

from __future__ import annotations

import html
import json
import warnings
from pathlib import Path as FilePath
from typing import Any

import umsgpack

with warnings.catch_warnings():  # meshcat 0.3.2 imports pyzmq's deprecated ioloop module
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat
    import meshcat.geometry as g
    from meshcat.animation import Animation
    from meshcat.servers.tree import SceneTree, find_node, walk
    from meshcat.servers.zmqserver import VIEWER_ROOT, create_command
    from pinocchio.visualize import MeshcatVisualizer

__all__ = ["Animation", "MeshcatVisualizer", "RecordingWindow", "g", "recording_visualizer",
           "static_html"]

_PAGE = """<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>{title}</title>
<style>
{css}</style>
</head>
<body>
<div id="meshcat-pane"></div>
<script>
{mainminjs}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
{commands}
</script>
{view}
</body>
</html>
"""
_HERE = FilePath(__file__).parent


class RecordingWindow:
    """The part of meshcat's ``ViewerWindow`` a ``Visualizer`` uses: ``send(command)``.

    Keeps the scene tree as meshcat's server does (``meshcat.servers.zmqserver``).
    """

    def __init__(self) -> None:
        self.tree = SceneTree()

    def send(self, command: Any) -> None:
        """Record one meshcat command (``SetObject``, ``SetTransform``, ...)."""
        data = command.lower()
        path = [p for p in data["path"].split("/") if p]
        blob = umsgpack.packb(data)
        kind = data["type"]
        if kind == "delete":
            if path:
                parent = find_node(self.tree, path[:-1])
                parent.pop(path[-1], None)
            else:
                self.tree = SceneTree()
            return
        node = find_node(self.tree, path)
        if kind == "set_object":
            node.object, node.properties = blob, []
        elif kind == "set_transform":
            node.transform = blob
        elif kind == "set_property":
            node.properties.append(blob)
        elif kind == "set_animation":
            node.animation = blob

    def __repr__(self) -> str:
        return "RecordingWindow()"


def recording_visualizer() -> meshcat.Visualizer:
    """A ``meshcat.Visualizer`` whose commands are recorded here, not sent to a server."""
    return meshcat.Visualizer.view_into(RecordingWindow(), meshcat.path.Path(("meshcat",)))


def static_html(vis: meshcat.Visualizer, title: str = "scara_opt",
                view: dict[str, Any] | None = None) -> str:
    """The self-contained HTML page of the recorded scene (meshcat's viewer inlined).

    ``view``: the data of scara_opt's part of the page (``SCARA_VIEW`` in ``page.js``);
    ``None``: meshcat's page alone.
    """
    commands = []
    for node in walk(vis.window.tree):
        if node.object is not None:
            commands.append(create_command(node.object))
        commands += [create_command(p) for p in node.properties]
        if node.transform is not None:
            commands.append(create_command(node.transform))
        if node.animation is not None:
            commands.append(create_command(node.animation))
    mainminjs = (FilePath(VIEWER_ROOT) / "main.min.js").read_text(encoding="utf-8")
    script = ""
    if view is not None:  # JSON is JavaScript; "</" would end the script element
        data = json.dumps(view, separators=(",", ":")).replace("</", "<\\/")
        script = (f"<script>\nvar SCARA_VIEW = {data};\n"
                  f"{(_HERE / 'page.js').read_text(encoding='utf-8')}</script>")
    css = (_HERE / "page.css").read_text(encoding="utf-8")
    return _PAGE.format(title=html.escape(title), css=css, mainminjs=mainminjs,
                        commands="".join(commands), view=script)
