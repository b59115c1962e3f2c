"""Opening ports by URL."""

from __future__ import annotations

import errno

import serial

from roboscript.errors import InputError, LinkError
from roboscript.transport.link import PortLike
from roboscript.transport.socketport import SocketPort, parse_socket_url

__all__ = ["HANDLER_PACKAGES", "open_port"]

WEB_SCHEMES = ("webserial", "webbluetooth")
"""The URL schemes of ports a student chose in the browser app
(:mod:`roboscript.transport.webport`)."""

HANDLER_PACKAGES = ("roboscript.transport.urlhandler", "roboscript.sim.urlhandler")
"""Where pyserial looks for ``protocol_<scheme>`` modules: transport's own (``lockstep://``,
``ble://``) and the simulator's ``sim://``, named rather than imported because the simulator
sits above transport."""
for _package in HANDLER_PACKAGES:
    if _package not in serial.protocol_handler_packages:
        serial.protocol_handler_packages.append(_package)


def open_port(url: str, *, baudrate: int = 115200) -> PortLike:
    """Open a serial port or URL for non-blocking reads.

    Args:
        url: A device path or a pyserial URL, ``sim://ROBOT?world=W&seed=N``, or in the browser
            app a port the student chose there (``webserial://1``, ``webbluetooth://1``).
        baudrate: Line speed in bits per second (ignored by sockets and ``sim://``).

    Raises:
        LinkError: The port does not exist, is busy, or refused the connection; the message
            names the port.
        InputError: A ``sim://`` URL names a world or profile file that is invalid
            (``file:line:col``), which is the user's input, not a port problem.
    """
    if url.partition("://")[0].lower() in WEB_SCHEMES:
        # the browser's ports (and the asyncio they use) load only for their URLs
        from roboscript.transport.webport import open_web_port

        return open_web_port(url, baudrate=baudrate)
    if url[:9].lower() == "socket://":
        try:
            address = parse_socket_url(url)
            if address is not None:  # plain host:port; options go to pyserial's handler
                return SocketPort(*address)
        except ValueError as exc:
            raise LinkError(f"cannot open {url}: {exc}") from exc
        except OSError as exc:
            raise LinkError(f"cannot open {url}: {_reason(exc)}") from exc
    try:
        port: PortLike = serial.serial_for_url(url, baudrate=baudrate, timeout=0, write_timeout=2)
    except serial.SerialException as exc:
        raise LinkError(f"cannot open {url}: {_reason(exc)}") from exc
    except InputError:
        raise
    except ValueError as exc:
        raise LinkError(f"cannot open {url}: {exc}") from exc
    return port


def _reason(exc: Exception) -> str:
    """Why a port did not open, decided by the error's type and errno, never by its text.

    pyserial keeps the errno on a device it could not open (``SerialException(errno, msg)``)
    and chains the socket's own ``OSError`` for ``socket://`` URLs it opens itself.
    """
    cause: BaseException | None = exc
    while cause is not None:
        if isinstance(cause, OSError):
            code = cause.errno
            if isinstance(cause, FileNotFoundError) or code == errno.ENOENT:
                return "there is no such port (is the robot plugged in? try 'roboscript ports')"
            if isinstance(cause, ConnectionRefusedError) or code == errno.ECONNREFUSED:
                return "nothing is listening there (is 'roboscript sim' running?)"
            if isinstance(cause, PermissionError) or code in (errno.EACCES, errno.EPERM):
                return "permission denied (on Linux, add yourself to the 'dialout' group)"
        cause = cause.__cause__ or cause.__context__
    return str(exc)
