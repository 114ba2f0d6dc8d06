"""Reading a URDF or MJCF document safely (shared by :mod:`featherdyn.readers.urdf` and :mod:`featherdyn.readers.mjcf`): bytes, encodings, the XML parser, messages.

The source is read as bytes and decoded (BOMs, UTF-16 with or without BOM, a
declared encoding); whitespace before the XML declaration is moved after it;
the parser is defusedxml's with DTDs, entities and XInclude refused, element
nesting bounded by :data:`MAX_DEPTH` and every attribute by
:data:`MAX_ATTRIBUTE_LENGTH` (checked while parsing); messages quote at most
:data:`QUOTE_LENGTH` characters of any value taken from the document.
:func:`parse_elements` (the MJCF loader's reader) parses a document that
cannot hold a DTD, an XInclude or too many elements with ElementTree's C
parser instead, and finds line numbers only for a message.
"""

from __future__ import annotations

import codecs
import errno
import os
import re
import stat
import warnings
from pathlib import Path
from typing import Any
from xml.etree.ElementTree import ParseError as _CParseError
from xml.etree.ElementTree import TreeBuilder
from xml.etree.ElementTree import XMLParser as _CXMLParser

from defusedxml import DefusedXmlException
from defusedxml.ElementTree import DefusedXMLParser, ParseError

from ..errors import ModelError, PhysicalityWarning, URDFError

#: Deepest element nesting accepted (real URDFs nest about 5 deep).
MAX_DEPTH = 1000
#: Longest attribute value accepted, in characters (a real URDF's longest is a mesh path of about 100).
MAX_ATTRIBUTE_LENGTH = 10_000
#: Characters of an offending value quoted in a message; the rest is elided and its length given.
QUOTE_LENGTH = 100
_XINCLUDE_NAMESPACES = ("http://www.w3.org/2001/XInclude", "http://www.w3.org/2003/XInclude")
# an XML declaration after leading whitespace (expat refuses it there; Pinocchio and MuJoCo accept the file)
_LATE_DECLARATION = re.compile(r"([ \t\r\n]+)(<\?xml[ \t\r\n][^>]*>)")
# UTF-16 without a BOM, recognised by "<?" or "<r" after optional whitespace
_UTF16_LE = re.compile(rb"(?:[ \t\r\n]\x00)*<\x00[?r]\x00")
_UTF16_BE = re.compile(rb"(?:\x00[ \t\r\n])*\x00<\x00[?r]")
# a quoted name in a message of the model builder, long enough to be shortened
_LONG_QUOTED = re.compile(f"'[^'\n]{{{QUOTE_LENGTH + 1},}}'|\"[^\"\n]{{{QUOTE_LENGTH + 1},}}\"")
_DECLARED_ENCODING = re.compile(rb"""^<\?xml[^>]*?encoding\s*=\s*["']([A-Za-z0-9._-]+)["']""")

# ---------------------------------------------------------------------------
# messages
# ---------------------------------------------------------------------------


def quote(value: str) -> str:
    """``repr(value)``; of a long value only the first :data:`QUOTE_LENGTH` characters, and its length."""
    if len(value) <= QUOTE_LENGTH:
        return repr(value)
    return f"{value[:QUOTE_LENGTH]!r}... ({len(value)} characters)"


def shorten(text: str) -> str:
    """``text``, cut after :data:`QUOTE_LENGTH` characters with its length said (for texts quoting the document)."""
    if len(text) <= QUOTE_LENGTH:
        return text
    return f"{text[:QUOTE_LENGTH]}... ({len(text)} characters)"


def shorten_quoted(message: str) -> str:
    """A message of the model builder with each long quoted name shortened as :func:`quote` would."""
    return _LONG_QUOTED.sub(lambda m: f"{m.group()[: QUOTE_LENGTH + 1]}{m.group()[0]}... ({len(m.group()) - 2} characters)", message)


# ---------------------------------------------------------------------------
# reading and decoding
# ---------------------------------------------------------------------------


def read_source(path_or_xml: Any, error: type[ModelError] = URDFError, kind: str = "URDF",
                 function: str = "load_urdf") -> tuple[str, str, str | None]:
    """``(text, label for messages, path or None)`` of a path, an XML string or XML bytes.

    ``error`` is the exception class raised (the MJCF loader passes its own),
    ``kind`` and ``function`` name the format and the caller in messages.
    """
    if isinstance(path_or_xml, (bytes, bytearray, memoryview)):
        return _decode(bytes(path_or_xml), "<bytes>", error), "<bytes>", None
    if isinstance(path_or_xml, str) and path_or_xml.lstrip("\ufeff \t\r\n").startswith("<"):
        text = path_or_xml.lstrip("\ufeff")
        if not text.isascii():
            _check_encodable(text, error)
        return text, "<string>", None
    if not isinstance(path_or_xml, (str, os.PathLike)):
        raise error(
            f"{function}: expected a path, an XML string or bytes, got {type(path_or_xml).__name__}"
        )
    label = path_or_xml if type(path_or_xml) is str and _normal_path(path_or_xml) else str(Path(path_or_xml))
    try:
        data = read_regular_file(label)[0]
    except (OSError, ValueError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise error(f"{label}: cannot read the {kind} file: {reason}") from None
    return _decode(data, label, error), label, label


def _check_encodable(text: str, error: type[ModelError]) -> None:
    """Refuse a ``str`` document holding a lone surrogate (``"\\udc80"``, e.g. from a ``surrogateescape`` decode):
    it is no Unicode character, so no XML text can hold it."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError as exc:
        line = text.count("\n", 0, exc.start) + 1
        raise error(f"<string>: line {line}: the character {text[exc.start]!r} (position {exc.start}) is a lone "
                    "surrogate, not a Unicode character: the text cannot be XML") from None


def _normal_path(path: str) -> bool:
    """Whether ``str(Path(path)) == path`` surely (POSIX separators, no empty or ``.`` parts, no trailing ``/``):
    the label of a path as given, without the cost of a ``Path`` (~25 µs after MuJoCo's compile)."""
    return (os.sep == "/" and os.altsep is None and bool(path) and "//" not in path and "/./" not in path
            and not path.startswith("./") and not path.endswith(("/", "/.")))


#: Largest model file read, in bytes.
MAX_FILE_BYTES = 200_000_000


def open_regular_file(path: str | os.PathLike[str]) -> tuple[int, os.stat_result]:
    """``(file descriptor, os.fstat)`` of a regular file opened for reading, without blocking: a named pipe or a
    device (``/dev/zero``, ``/dev/stdin``) is refused at once with an ``OSError`` rather than read forever."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_BINARY", 0) | getattr(os, "O_NONBLOCK", 0))
    try:
        status = os.fstat(fd)
        if not stat.S_ISREG(status.st_mode):
            raise OSError(errno.EINVAL, "not a regular file (a directory, device or pipe)")
    except OSError:
        os.close(fd)
        raise
    return fd, status


def read_regular_file(path: str | os.PathLike[str], limit: int = MAX_FILE_BYTES) -> tuple[bytes, os.stat_result]:
    """The bytes of a regular file of at most ``limit`` bytes, and its status (``os.fstat`` of what was read).

    Read with the operating system's calls alone (``Path.read_bytes`` makes
    more system calls, ``io``'s buffering and terminal checks, which cost a
    model's load ~30 µs after other work). Opened by :func:`open_regular_file`:
    ``OSError`` (``strerror`` says why) for a pipe, a device or a larger file.
    """
    fd, status = open_regular_file(path)
    try:
        if status.st_size > limit:
            raise OSError(errno.EFBIG, f"{status.st_size} bytes, more than the {limit} read")
        chunks = []
        left = status.st_size
        while left > 0 and (chunk := os.read(fd, left)):  # a file that grows meanwhile is read to its first size
            chunks.append(chunk)
            left -= len(chunk)
    finally:
        os.close(fd)
    return b"".join(chunks), status


def _decode(data: bytes, label: str, error: type[ModelError] = URDFError) -> str:
    """Decode XML bytes: a BOM wins, then UTF-16 sniffing, then the declared encoding, then UTF-8."""
    encoding = "utf-8"
    if data[:1] == b"<" and data[1:2] != b"\x00" and (data[:5] != b"<?xml" or b"encoding" not in data[:data.find(b">")]):
        pass  # no BOM, not UTF-16, no declared encoding (the usual file): UTF-8, without the regular expressions
    else:
        encoding = _sniffed_encoding(data, label, error)
    try:
        return data.decode(encoding)
    except LookupError:  # a declared bytes-to-bytes codec such as "zlib" or "base64"
        raise error(
            f"{label}: the XML declaration names {quote(encoding)}, which is not a text encoding"
        ) from None
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise error(
            f"{label}: line {line}: bytes are not valid {encoding} (byte {data[exc.start:exc.start + 1]!r} "
            f"at offset {exc.start}); save the file as UTF-8"
        ) from None


def _sniffed_encoding(data: bytes, label: str, error: type[ModelError]) -> str:
    """The encoding of XML bytes (:func:`_decode`'s rules)."""
    boms = (
        (codecs.BOM_UTF32_LE, "utf-32"),
        (codecs.BOM_UTF32_BE, "utf-32"),
        (codecs.BOM_UTF8, "utf-8-sig"),
        (codecs.BOM_UTF16_LE, "utf-16"),
        (codecs.BOM_UTF16_BE, "utf-16"),
    )
    encoding = "utf-8"
    for bom, enc in boms:
        if data.startswith(bom):
            encoding = enc
            break
    else:
        if _UTF16_LE.match(data):
            encoding = "utf-16-le"
        elif _UTF16_BE.match(data):
            encoding = "utf-16-be"
        else:
            declared = _DECLARED_ENCODING.match(data.lstrip())
            if declared:
                name = declared.group(1).decode("ascii")
                try:
                    info = codecs.lookup(name)
                except LookupError:
                    raise error(f"{label}: unknown encoding {quote(name)} in the XML declaration") from None
                if info.name.startswith("utf-16") or info.name.startswith("utf-32"):
                    # declared UTF-16 but no BOM and ASCII-readable: the declaration is wrong
                    raise error(
                        f"{label}: the XML declaration says {quote(name)} but the bytes are not UTF-16/32"
                    )
                encoding = info.name
    return encoding


# ---------------------------------------------------------------------------
# XML
# ---------------------------------------------------------------------------


class _Builder:
    """ElementTree parser target that bounds nesting, rejects XInclude and records line numbers."""

    def __init__(self, label: str, error: type[ModelError] = URDFError, kind: str = "URDF") -> None:
        self._tb = TreeBuilder()
        self._label = label
        self._error = error
        self._kind = kind
        self._depth = 0
        self.expat: Any = None
        self.lines: dict[Any, int] = {}
        self.line_depth = 4

    def line(self) -> int:
        return int(self.expat.CurrentLineNumber) if self.expat is not None else 0

    def start(self, tag: str, attrib: dict[str, str]) -> Any:
        self._depth += 1
        if self._depth > MAX_DEPTH:
            raise self._error(f"{self._label}: line {self.line()}: elements nested deeper than {MAX_DEPTH} levels")
        if tag.startswith("{") and tag[1:].split("}", 1)[0] in _XINCLUDE_NAMESPACES:
            raise self._error(f"{self._label}: line {self.line()}: XInclude ({shorten(tag)}) is not allowed in a {self._kind}")
        for key, value in attrib.items():
            if len(value) > MAX_ATTRIBUTE_LENGTH:
                raise self._error(
                    f"{self._label}: line {self.line()}: <{shorten(tag)}{_name_attribute(attrib)}>: "
                    f"{shorten(key)}={quote(value)}: expected at most {MAX_ATTRIBUTE_LENGTH} characters "
                    f"(MAX_ATTRIBUTE_LENGTH), got {len(value)}"
                )
        elem = self._tb.start(tag, attrib)
        if self._depth <= self.line_depth:
            self.lines[elem] = self.line()
        return elem

    def end(self, tag: str) -> Any:
        self._depth -= 1
        return self._tb.end(tag)

    def data(self, data: str) -> None:
        self._tb.data(data)

    def close(self) -> Any:
        return self._tb.close()


def _name_attribute(attrib: dict[str, str]) -> str:
    """`` name='...'`` for an element's message, or ``""``."""
    name = attrib.get("name")
    return f" name={quote(name)}" if name is not None and len(name) <= MAX_ATTRIBUTE_LENGTH else ""


def _declaration_first(text: str) -> str:
    """Move whitespace that precedes the XML declaration to just after it (line numbers stay right below it)."""
    if text[:1] not in (" ", "\t", "\r", "\n"):  # the usual text: no regular expression needed
        return text
    late = _LATE_DECLARATION.match(text)
    if late is None:
        return text
    return late.group(2) + late.group(1) + text[late.end():]


def parse_xml(text: str, label: str, error: type[ModelError] = URDFError, kind: str = "URDF",
               line_depth: int = 4) -> tuple[Any, dict[Any, int]]:
    """The root element and the line number of each element up to depth ``line_depth``."""
    text = _declaration_first(text)
    builder = _Builder(label, error, kind)
    builder.line_depth = line_depth
    parser = DefusedXMLParser(target=builder, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    builder.expat = parser.parser
    try:
        parser.feed(text)
        root = parser.close()
    except error:
        raise
    except ParseError as exc:
        line = exc.position[0] if getattr(exc, "position", None) else builder.line()
        raise error(f"{label}: line {line}: malformed XML: {shorten(str(exc))}") from None
    except DefusedXmlException as exc:
        what = type(exc).__name__.replace("Forbidden", "")
        raise error(
            f"{label}: line {builder.line()}: {what} declarations are not allowed in a {kind} "
            f"(refused for safety: {shorten(str(exc))})"
        ) from None
    except RecursionError:
        raise error(f"{label}: XML nested too deeply") from None
    except (ValueError, MemoryError) as exc:  # e.g. NUL characters in a str
        raise error(f"{label}: cannot parse the XML: {shorten(str(exc))}") from None
    return root, builder.lines


class ElementLines:
    """The line of each element of one parsed text, by document-order index, computed when first asked for.

    :func:`parse_elements`'s C-parser path has no line numbers (ElementTree's C parser does not report them); a
    message that needs one parses the text again with :func:`parse_xml`, which records them.
    """

    def __init__(self, text: str, label: str, lines: list[int] | None = None) -> None:
        self.text = text
        self.label = label
        self._lines = lines

    def line(self, index: int) -> int:
        """The line of the element at ``index`` in document order (``0``: unknown)."""
        if self._lines is None:
            _, lines = parse_xml(self.text, self.label, line_depth=MAX_DEPTH)
            self._lines = list(lines.values())
        return self._lines[index] if 0 <= index < len(self._lines) else 0


class ElementIndex:
    """Each element's index in document order (``index[elem]``, ``index.get(elem)``), made from the parsed list when
    first asked for: only a message asks."""

    def __init__(self, elements: list[Any]) -> None:
        self._elements = elements
        self._index: dict[Any, int] | None = None

    def get(self, elem: Any, default: int | None = None) -> int | None:
        if self._index is None:
            self._index = dict(zip(self._elements, range(len(self._elements)), strict=True))
        return self._index.get(elem, default)

    def __getitem__(self, elem: Any) -> int:
        k = self.get(elem)
        if k is None:
            raise KeyError(elem)
        return k


def parse_elements(text: str, label: str, error: type[ModelError] = URDFError,
                   kind: str = "URDF") -> tuple[Any, ElementIndex, ElementLines]:
    """``(root, document-order index of each element, their lines)``: :func:`parse_xml` with lines on demand.

    A text without a DTD cannot declare an entity (undefined ones are expat's own error), so it is parsed by
    ElementTree's C parser, ~3× faster than defusedxml's Python one; its nesting is bounded because it has at
    most :data:`MAX_DEPTH` elements, its attributes because it is shorter than :data:`MAX_ATTRIBUTE_LENGTH`
    (otherwise they are measured). Any other text — a ``<!DOCTYPE``, more elements, a possible XInclude, a NUL —
    takes :func:`parse_xml`'s guarded path, which also words the refusals.
    """
    text = _declaration_first(text)
    root = None
    if "<!DOCTYPE" not in text and "XInclude" not in text and "\x00" not in text:
        parser = _CXMLParser()
        try:
            parser.feed(text)
            root = parser.close()
        except _CParseError:
            root = None  # the guarded parse words the message
        if root is not None:
            elements = list(root.iter())
            # an attribute value holds no "<": a longer one needs as long a stretch of text without "<"
            if len(elements) > MAX_DEPTH or (len(text) > MAX_ATTRIBUTE_LENGTH
                                             and max(map(len, text.split("<"))) > MAX_ATTRIBUTE_LENGTH and any(
                    len(v) > MAX_ATTRIBUTE_LENGTH for e in elements for v in e.attrib.values())):
                root = None
    lines: list[int] | None = None  # the C parser's: found when a message asks
    if root is None:
        root, found = parse_xml(text, label, error, kind, line_depth=MAX_DEPTH)
        lines = list(found.values())
        elements = list(root.iter())
    return root, ElementIndex(elements), ElementLines(text, label, lines)


def local_name(tag: Any, ns: str) -> str:
    """The element's name with the root's namespace removed (other namespaces kept: ``{x}link`` is not a link)."""
    if not isinstance(tag, str):  # comments, processing instructions
        return ""
    if ns and tag.startswith(ns):
        return tag[len(ns):]
    return tag


def reissue_warnings(caught: list[warnings.WarningMessage], label: str) -> None:
    """Re-issue the warnings caught while a loader built its model: physicality warnings prefixed with the file's
    ``label`` (attributed to the loader's caller), the others unchanged."""
    for w in caught:
        if issubclass(w.category, PhysicalityWarning):
            warnings.warn(f"{label}: {shorten_quoted(str(w.message))}", PhysicalityWarning, stacklevel=3)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
