"""Opening ports by URL."""

from __future__ import annotations

import serial

from roboscript.errors import InputError, LinkError
from roboscript.transport.link import PortLike
from roboscript.transport.socketport import SocketPort, parse_socket_url

__all__ = ["open_port"]

_HANDLERS = "roboscript.transport.urlhandler"
if _HANDLERS not in serial.protocol_handler_packages:
    serial.protocol_handler_packages.append(_HANDLERS)


def open_port(url: str, *, baudrate: int = 115200) -> PortLike:
    """Open a serial port or URL for non-blocking reads.

    Args:
        url: A device path or a pyserial URL, or ``sim://ROBOT?world=W&seed=N``.
        baudrate: Line speed in bits per second (ignored by sockets and ``sim://``).

    Raises:
        LinkError: The port does not exist, is busy, or refused the connection; the message
            names the port.
        InputError: A ``sim://`` URL names a world or profile file that is invalid
            (``file:line:col``), which is the user's input, not a port problem.
    """
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
    text = str(exc)
    if "No such file" in text or ("could not open port" in text and "2]" in text):
        return "there is no such port (is the robot plugged in? try 'roboscript ports')"
    if "Connection refused" in text or "111" in text:
        return "nothing is listening there (is 'roboscript sim' running?)"
    if "Permission denied" in text:
        return "permission denied (on Linux, add yourself to the 'dialout' group)"
    return text
