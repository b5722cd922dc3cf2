"""``mechgen view MODEL.py``: the page served by a Bokeh server started in this process on
127.0.0.1 (a free port). A parameter slider solves the whole cycle again with the
compiled module (Explorer.compute) and sends the new columns; the assembly modes at the
time shown are found on request; the model file is watched, and when it changes on disk
it is built again and every open page redrawn (edit, then see)."""
from __future__ import annotations

import asyncio
import os
import socket
import threading
import traceback

from ..errors import MechgenError
from .page import Page

WATCH_MS = 500           # how often the model file is looked at


def free_port(host="127.0.0.1") -> int:
    with socket.socket() as s:
        s.bind((host, 0))
        return s.getsockname()[1]


class Session:
    """One open page: its Explorer (its own parameter values) and Page."""

    def __init__(self, doc, make_explorer, watch=None):
        self.doc, self.make, self.watch = doc, make_explorer, watch
        self.stamp = _stamp(watch)
        self.page = None
        try:
            ex = make_explorer()
        except Exception as exc:   # a page opened while the file is broken: say why
            if not watch:
                raise
            traceback.print_exc()
            self.broken(exc)
        else:
            self.build(ex)
        if watch:
            doc.add_periodic_callback(self.look, WATCH_MS)

    def broken(self, exc):
        """The page of a model file that does not build (opened, or reloaded, while it
        is being edited): the error, in place of the view, until the file builds."""
        from bokeh.layouts import column
        from bokeh.models import CustomJS, Div
        from .page import BANNER
        self.reloader = Div(text="", visible=False, name="reloader")
        self.reloader.js_on_change("text", CustomJS(code="window.location.reload();"))
        self.error = Div(text=_cannot_open(self.watch, exc), name="banner",
                         render_as_text=True, width=720, styles=BANNER)
        self.doc.clear()
        self.doc.title = f"mechgen view: {os.path.basename(self.watch)} does not build"
        self.doc.add_root(column(self.error, self.reloader))

    def build(self, ex):
        self.ex = ex
        self.page = Page(ex, server=True)
        doc = self.doc
        # the button's callback before the layout joins the document: Bokeh (3.9) subscribes
        # a model's event callbacks to its document when the model is attached, and no
        # longer when on_click is called later (a click then reached no callback)
        self.page.mode_button.on_click(self.find_modes)
        doc.clear()
        doc.title = f"mechgen view: {ex.mech.name}"
        doc.add_root(self.page.layout)
        doc.js_on_event("document_ready", self.page.redraw)
        for name, slider in self.page.sliders.items():
            slider.on_change("value", lambda attr, old, new, name=name: self.moved(name, new))
        self.page.modes.on_change("value", lambda attr, old, new: self.choose_mode(new))
        for sel in self.page.selects + [self.page.against]:
            sel.on_change("value", lambda attr, old, new: self.choose())
        self._modes = {}
        self.data = ex.data            # every column of the cycle shown
        self.pending, self.busy = {}, False    # parameter values not yet solved (moved)
        self.lock, self.solving = threading.Lock(), threading.Lock()

    def choose(self):
        self.doc.hold("combine")
        try:
            self.page.choose(self.data)
        finally:
            self.doc.unhold()

    def moved(self, name, value):
        """A parameter's slider or value box changed: the value kept, and the cycle solved
        for the latest values by the session's worker (solve_pending). Changes arriving
        while a cycle is being solved are coalesced into the next solve: the latest value
        of each parameter wins and none is lost; the page is never sent an older cycle
        after a newer one."""
        with self.lock:
            self.pending[name] = float(value)
            if self.busy:
                return
            self.busy = True
        threading.Thread(target=self.solve_pending, name="mechgen-view-solve",
                         daemon=True).start()

    def solve_pending(self):
        """(A worker thread, one at a time per session.) Solve the cycle for the values
        pending, hand it to the server's loop (send) and wait until it is applied, then
        again while values arrived meanwhile; the server's loop keeps reading the page's
        messages all the while."""
        while True:
            with self.lock:
                changes, self.pending = self.pending, {}
                if not changes:
                    self.busy = False
                    return
            applied = threading.Event()
            try:
                with self.solving:
                    data, again, message = self.ex.compute(changes)
            except Exception:           # never leave the page waiting without a word
                traceback.print_exc()
                continue
            self.doc.add_next_tick_callback(
                lambda: self.send(data, again, message, applied))
            applied.wait(30)

    def send(self, data, again, message, applied=None):
        """The new cycle to the page in one message (one redraw in the browser)."""
        try:
            self.data = data
            self.doc.hold("combine")
            try:
                self.page.show(data, self.ex.picture if again else None, message)
            finally:
                self.doc.unhold()
        finally:
            if applied is not None:
                applied.set()

    def find_modes(self):
        t = self.page.time.value
        try:
            with self.solving:
                found = self.ex.modes(t)
        except MechgenError as exc:
            self.page.note.text = f"assembly modes at T = {t:.4g}: {exc}"
            return
        self._modes = dict(found)
        self.page.modes.options = [label for label, _ in found]
        self.page.note.text = f"{len(found)} assembly mode(s) at T = {t:.4g}"

    def choose_mode(self, label):
        q = self._modes.get(label)
        if q is None:
            return
        try:
            with self.solving:
                start = self.ex.follow_back(q, self.page.time.value)
        except MechgenError as exc:
            self.page.note.text = f"{label} cannot be followed back to the cycle's start: {exc}"
            return
        with self.solving:
            data, again, message = self.ex.compute(guess=start)
        self.send(data, again, message)

    def look(self):
        """When the model file changed on disk: build it, then reload the page (a fresh
        session builds the view anew, from the module now up to date)."""
        stamp = _stamp(self.watch)
        if stamp == self.stamp:
            return
        self.stamp = stamp
        try:
            self.make()
        except Exception as exc:          # a model being edited may be broken: say so,
            traceback.print_exc()         # above the drawing, until it builds again
            if self.page is None:
                self.error.text = _cannot_open(self.watch, exc)
            else:
                self.page.banner.text = f"{os.path.basename(self.watch)} changed but " \
                    f"does not build: {type(exc).__name__}: {exc}\nThe page shows the " \
                    f"model as it last built; save a fix to see it."
                self.page.banner.visible = True
            return
        (self.page or self).reloader.text = repr(stamp)


def _cannot_open(path, exc) -> str:
    return f"{os.path.basename(path)} does not build: {type(exc).__name__}: {exc}\n" \
           f"This page shows the view once it builds: save a fix."


def _stamp(path):
    if not path:
        return None
    try:
        st = os.stat(path)
    except OSError:
        return None
    return (st.st_mtime_ns, st.st_size)


def _no_delay(tornado_app):
    """Send the page's websocket messages at once. Bokeh writes a message as several small
    frames; with Nagle's algorithm on, a frame after the first waits for the browser's
    delayed acknowledgement (~40 ms on Linux): a slider's answer took 50 ms where 10
    suffice. tornado's WebSocketHandler.set_nodelay is the documented cure; the view's
    server uses, for its websocket route, a handler that calls it when a page connects."""
    from bokeh.server.views.ws import WSHandler

    class NoDelay(WSHandler):
        def open(self):
            self.set_nodelay(True)
            return super().open()

    for router in (tornado_app.wildcard_router, tornado_app.default_router):
        for rule in getattr(router, "rules", ()):
            if rule.target is WSHandler:
                rule.target = NoDelay
            for inner in getattr(rule.target, "rules", ()):
                if inner.target is WSHandler:
                    inner.target = NoDelay


class ViewServer:
    """A Bokeh server for the view, in a thread of this process (``start()``; the page's
    address is ``url``; ``stop()``)."""

    def __init__(self, make_explorer, watch=None, port=None, host="127.0.0.1"):
        self.make, self.watch, self.host = make_explorer, watch, host
        self.port = port or free_port(host)
        self.url = f"http://{host}:{self.port}/"
        self._thread = None
        self._server = None
        self._ready = threading.Event()
        self._error = None

    def _app(self):
        from bokeh.application import Application
        from bokeh.application.handlers.function import FunctionHandler
        return Application(FunctionHandler(lambda doc: Session(doc, self.make, self.watch)))

    def _run(self):
        from bokeh.server.server import Server
        from tornado.ioloop import IOLoop
        asyncio.set_event_loop(asyncio.new_event_loop())
        try:
            self._server = Server({"/": self._app()}, io_loop=IOLoop.current(),
                                  address=self.host, port=self.port,
                                  allow_websocket_origin=[f"{self.host}:{self.port}",
                                                          f"localhost:{self.port}"])
            _no_delay(self._server._tornado)
            self._server.start()
        except Exception as exc:
            self._error = exc
            self._ready.set()
            return
        self._ready.set()
        self._server.io_loop.start()

    def start(self):
        self._thread = threading.Thread(target=self._run, name="mechgen-view", daemon=True)
        self._thread.start()
        self._ready.wait(30)
        if self._error is not None:
            raise MechgenError(f"the view's server did not start on {self.url}: {self._error}")
        return self

    def stop(self):
        if self._server is not None:
            loop = self._server.io_loop
            loop.add_callback(self._server.stop)
            loop.add_callback(loop.stop)
        if self._thread is not None:
            self._thread.join(5)

    def serve_forever(self):
        """Block until Ctrl-C."""
        try:
            while self._thread.is_alive():
                self._thread.join(0.5)
        except KeyboardInterrupt:
            self.stop()
