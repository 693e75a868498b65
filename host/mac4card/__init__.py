"""mac4 - the host side of the MACCON MAC4 axis controller.

    import mac4card
    with mac4card.connect("sim:inc") as card:           # or "socket://127.0.0.1:PORT", "/dev/ttyS0"
        card.command("WAP", 8000, axis=0)           # axis 0 = the manual's axis 1
        card.wait_for("pos_end", axis=0, timeout=5)

Commands, status bits, error codes and modes all come from the card's
command dictionary, build/commands.json (generated from
firmware/commands.def and firmware/status.def).  docs/host-client.md.
"""
from .card import Card, CardError, Response, Status, Timeout, connect
from .dictionary import (Command, Dictionary, Mac4Error, check_dictionary, is_number,
                         load_dictionary, looks_like_number, parse_number, s32)
from . import board  # noqa: F401  (the memory map, generated from board/mac4.toml)
from .faults import decode_fault_record, exception_name, read_fault_record
from .paths import find_dictionary, find_sim
from .telegram import (DLE, NAK, STX, ChecksumError, Garbage, Nak, Telegram, TelegramDecoder,
                       checksum, encode_telegram, telegram_data)
from .transport import SerialTransport, SimTransport, TransportError, open_transport

__all__ = ["Card", "CardError", "ChecksumError", "Command", "Dictionary", "Garbage", "Mac4Error",
           "Nak", "Response", "SerialTransport", "SimTransport", "Status", "Telegram",
           "TelegramDecoder", "Timeout", "TransportError", "check_dictionary", "checksum",
           "connect", "decode_fault_record", "encode_telegram", "exception_name", "find_dictionary", "find_sim", "is_number",
           "load_dictionary", "looks_like_number", "open_transport", "parse_number", "read_fault_record", "s32", "telegram_data",
           "DLE", "NAK", "STX"]
