#!/usr/bin/env python3
"""Independent reader of pbrtc scene archives (.pbrta).

Written from format/ARCHIVE.md and format/SCHEMA.md alone, never from
pbrtc's sources, and kept in the test suite so that the spec stays complete
enough for a stranger to read an archive: change the format without the
spec, and this reader fails on what pbrtc writes.

usage: read_pbrta.py --schema PATH/SCHEMA.md [--pbrtc PATH/pbrtc] [-v] FILE.pbrta...

Each file is read and checked as ARCHIVE.md section 10 asks, except that
Draco streams (codec 2) are not decoded: only their checksum, framing and the
array layout their mesh records claim are checked. With --pbrtc, the output
of `pbrtc --info FILE` must equal the summary this reader prints in the same
layout (a unified diff shows any difference). -v prints that summary and the
records read. Per file, the last line is `FILE: ok (...)` or
`FILE: error: <reason>`. Exit status: 0 if every file is ok, 1 if any is not,
2 for usage errors and for an exception none of the reader's checks raised (a
check it lacks, or a bug: printed with its traceback, never taken for a
correct refusal).

Standard library only, plus libzstd and libxxhash through ctypes.
"""
import argparse
import array
import ctypes
import ctypes.util
import difflib
import math
import re
import shutil
import struct
import subprocess
import sys
import traceback
from collections import namedtuple


def _library(name, fallback):
    return ctypes.CDLL(ctypes.util.find_library(name) or fallback)


_zstd = _library("zstd", "/usr/lib/x86_64-linux-gnu/libzstd.so.1")
_xxh = _library("xxhash", "/usr/lib/x86_64-linux-gnu/libxxhash.so.0")
_size_t, _vp = ctypes.c_size_t, ctypes.c_void_p
for _f, _res, _args in (("ZSTD_findFrameCompressedSize", _size_t, [_vp, _size_t]),
                        ("ZSTD_getFrameContentSize", ctypes.c_ulonglong, [_vp, _size_t]),
                        ("ZSTD_decompress", _size_t, [_vp, _size_t, _vp, _size_t]),
                        ("ZSTD_isError", ctypes.c_uint, [_size_t]),
                        ("ZSTD_getErrorName", ctypes.c_char_p, [_size_t])):
    getattr(_zstd, _f).restype, getattr(_zstd, _f).argtypes = _res, _args
_xxh.XXH3_64bits.restype, _xxh.XXH3_64bits.argtypes = ctypes.c_uint64, [_vp, _size_t]

ZSTD_MAGIC = b"\x28\xb5\x2f\xfd"
ZSTD_CONTENTSIZE_UNKNOWN, ZSTD_CONTENTSIZE_ERROR = 2**64 - 1, 2**64 - 2


class ArchiveError(Exception):
    pass


class CodecError(Exception):
    """A section's stored bytes do not decode as its codec says."""


def xxh3(data):
    data = bytes(data)
    return _xxh.XXH3_64bits(data, len(data))


def zstd_frame(data, size):
    """Decode data that must be exactly one zstd frame recording `size` as its content size."""
    data = bytes(data)
    n = _zstd.ZSTD_findFrameCompressedSize(data, len(data))
    if data[:4] != ZSTD_MAGIC or _zstd.ZSTD_isError(n):
        raise CodecError("not a zstd frame")
    if n != len(data):
        raise CodecError(f"{len(data) - n} bytes after the zstd frame")
    content = _zstd.ZSTD_getFrameContentSize(data, len(data))
    if content in (ZSTD_CONTENTSIZE_UNKNOWN, ZSTD_CONTENTSIZE_ERROR):
        raise CodecError("zstd frame does not record its content size")
    if content != size:
        raise CodecError(f"zstd content size {content}, expected {size}")
    out = bytearray(size or 1)  # ZSTD_decompress wants a real buffer even for 0 bytes
    got = _zstd.ZSTD_decompress((ctypes.c_char * len(out)).from_buffer(out), size, data, len(data))
    if _zstd.ZSTD_isError(got):
        raise CodecError(f"zstd: {_zstd.ZSTD_getErrorName(got).decode()}")
    if got != size:
        raise CodecError(f"zstd decoded {got} bytes, expected {size}")
    return out if size else bytearray()


MiB = 1 << 20


def unshuffle(src, dst, at):
    """Undo the byte shuffle of one block (src, a whole frame's bytes) into dst[at:] (section 5)."""
    m = len(src)
    n = m // 4
    for k in range(4):
        dst[at + k: at + 4 * n: 4] = src[k * n: (k + 1) * n]
    dst[at + 4 * n: at + m] = src[4 * n: m]


# ---------------------------------------------------------------- schema

WORDS_PER_ELEMENT = {"int": 1, "float": 1, "bool": 1, "string": 1, "point2": 2, "vector2": 2,
                     "point3": 3, "vector3": 3, "normal": 3, "rgb": 3,
                     "float texture": 1, "spectrum texture": 3}
Param = namedtuple("Param", "name kind arity default flags")


class Schema:
    """SCHEMA.md as tables: category names, and per category its types as (name, [Param])."""

    def __init__(self, path):
        self.category_names, self.types = [], []
        for line in open(path, encoding="utf-8"):
            if m := re.match(r"## Category (\d+): (.+)", line):
                if int(m[1]) != len(self.types):
                    raise ValueError(f"category {m[1]} out of order")
                self.category_names.append(m[2].strip())
                self.types.append([])
            elif m := re.match(r"### .+ (\d+): `([^`]+)`", line):
                if int(m[1]) != len(self.types[-1]):
                    raise ValueError(f"type {m[1]} ({m[2]}) out of order")
                self.types[-1].append((m[2], []))
            elif m := re.match(r"\| (\d+) \| `([^`]+)` \| ([a-z0-9 ]+) \| (\d+) \| (.*?) \| (.*)\|$", line):
                params = self.types[-1][-1][1]
                if int(m[1]) != len(params) or m[3] not in WORDS_PER_ELEMENT:
                    raise ValueError(f"bad parameter row: {line.strip()}")
                params.append(Param(m[2], m[3], int(m[4]), m[5].strip(), m[6].strip()))
        if not self.types:
            raise ValueError("no categories")
        self.category = {name: i for i, name in enumerate(self.category_names)}


def parse_default(p):
    """The schema's listed default as values ([] for `required` or none); for a computed
    default this is only the placeholder."""
    if p.kind == "string":
        return [p.default.strip('"')] if p.default.startswith('"') else []
    try:
        conv = float if p.kind not in ("int", "bool") else int
        return [conv(x) for x in p.default.split()]
    except ValueError:
        return []


# ---------------------------------------------------------------- archive layout

NONE = 0xFFFFFFFF
MAGIC = b"\x89PBRTA\r\n"
MAJOR, MINOR = 2, 1
KINDS = {1: "scene", 2: "strings", 3: "entities", 4: "values", 5: "words", 6: "transforms",
         7: "textures", 8: "materials", 9: "media", 10: "lights", 11: "area_lights",
         12: "shapes", 13: "objects", 14: "object_shapes", 15: "instances", 16: "meshes",
         17: "geometry", 18: "images", 19: "texels", 20: "provenance"}
SCENE, STRINGS, ENTITIES, VALUES, WORDS, TRANSFORMS, TEXTURES, MATERIALS, MEDIA, LIGHTS, \
    AREA_LIGHTS, SHAPES, OBJECTS, OBJECT_SHAPES, INSTANCES, MESHES, GEOMETRY, IMAGES, \
    TEXELS, PROVENANCE = range(1, 21)
RAW, ZSTD, DRACO = 0, 1, 2
CODECS = {RAW: "raw", ZSTD: "zstd", DRACO: "draco"}
CHUNK_SIZE = 1 << 20  # a raw section's checksum chunks (section 5)
# Array kinds: SceneRecord count field, element size and record layout (section 6 and 7).
ARRAYS = {ENTITIES: ("num_entities", 16, "<BBHIII"), VALUES: ("num_values", 16, "<4I"),
          WORDS: ("num_words", 4, "<I"), TRANSFORMS: ("num_transforms", 272, "<34d"),
          TEXTURES: ("num_textures", 16, "<4I"), MATERIALS: ("num_materials", 16, "<4I"),
          MEDIA: ("num_media", 16, "<4I"), LIGHTS: ("num_lights", 16, "<4I"),
          AREA_LIGHTS: ("num_area_lights", 4, "<I"), SHAPES: ("num_shapes", 40, "<10I"),
          OBJECTS: ("num_objects", 16, "<4I"), OBJECT_SHAPES: ("num_object_shapes", 4, "<I"),
          INSTANCES: ("num_instances", 16, "<4I"), MESHES: ("num_meshes", 72, "<4I6Q2I"),
          IMAGES: ("num_images", 64, "<6IQ8I")}
SCENE_FIELDS = ("camera camera_transform camera_medium film filter sampler integrator accelerator "
                "num_entities num_values num_words num_strings num_transforms num_textures "
                "num_materials num_media num_lights num_area_lights num_shapes num_objects "
                "num_object_shapes num_instances num_meshes num_images").split()
Texture = namedtuple("Texture", "entity reserved transform image")
Material = namedtuple("Material", "entity reserved mix0 mix1")
Medium = namedtuple("Medium", "entity transform reserved0 reserved1")
Light = namedtuple("Light", "entity transform medium image")
Shape = namedtuple("Shape", "entity mesh material area_light inside_medium outside_medium "
                            "transform object flags reserved")
Object = namedtuple("Object", "reserved first_shape num_shapes provenance")
Instance = namedtuple("Instance", "object transform provenance reserved")
Mesh = namedtuple("Mesh", "num_vertices num_triangles flags section positions normals "
                          "tangents uv indices face_indices refine_level source_shape")
Image = namedtuple("Image", "width height channels levels format section offset wrap "
                            "distribution source_width source_height source_image r0 r1 r2")
# Mesh arrays in layout order: (field, flag bit or None if always present, bytes per vertex or
# per triangle, counted per triangle?)
MESH_ARRAYS = (("positions", None, 12, False), ("normals", 1, 12, False), ("tangents", 2, 12, False),
               ("uv", 4, 8, False), ("indices", None, 12, True), ("face_indices", 8, 4, True))
TEXEL_BYTES = {0: 4, 1: 2, 2: 1}
# Bit names as `pbrtc --info` prints them (ARCHIVE.md section 4 calls bit 7 "alpha masks").
EFFECTS = ["media", "motion blur", "textures", "area lights", "infinite lights",
           "subsurface", "instancing", "alpha masks"]


def align16(n):
    return (n + 15) // 16 * 16


def fmt_size(n):
    if n < 1024:
        return f"{n} B"
    return f"{n / 1024:.1f} KiB" if n < MiB else f"{n / MiB:.2f} MiB"


class Section:
    def __init__(self, index, fields):
        self.index = index
        (self.kind, self.codec, self.offset, self.stored_size, self.raw_size, self.checksum,
         self.count, self.reserved) = fields
        self.name = KINDS.get(self.kind, f"kind {self.kind}")
        self.raw = None  # decoded bytes; stays None for Draco
        self.frames = []  # zstd: each frame's stored size
        self.frame_size, self.shuffled = 0, False


class Archive:
    def __init__(self, path, schema):
        self.path, self.schema = path, schema

    def fail(self, msg, where=None):
        """where: a Section, or a section kind (its section, if present, is named)."""
        if isinstance(where, int):
            where = self.sections_of.get(where, [None])[0]
        raise ArchiveError(f"section '{where.name}' (#{where.index}): {msg}" if where else msg)

    def check_index(self, value, limit, what, where, none_ok=False):
        if value >= limit and not (none_ok and value == NONE):
            self.fail(f"{what} {value} out of range ({limit})", where)

    def read(self):
        with open(self.path, "rb") as f:
            self.data = f.read()
        self.sections_of = {}
        self.read_layout()
        for s in self.sections:
            self.decode(s)
        self.read_records()

    # ------------------------------------------------------------ layout

    def read_layout(self):
        d = self.data
        if len(d) < 64 or d[:8] != MAGIC:
            self.fail("not a pbrtc archive (bad magic)")
        (self.major, self.minor, flags, self.effects, nsec, reserved, table_offset, file_size,
         table_checksum, header_checksum) = struct.unpack_from("<HHIQIIQQQQ", d, 8)
        if xxh3(d[:56]) != header_checksum:
            self.fail("header checksum mismatch")
        # self.effects is the writer's summary: not cross-checked against the records (section 4).
        if self.major != MAJOR:
            self.fail(f"archive version {self.major}.{self.minor}: this reader reads {MAJOR}.x")
        if flags or reserved:
            self.fail("header reserved fields not 0")
        if table_offset != 64:
            self.fail(f"table_offset {table_offset}, expected 64")
        if file_size != len(d):
            self.fail(f"file_size {file_size} but the file has {len(d)} bytes")
        table_end = 64 + 48 * nsec
        if table_end > len(d):
            self.fail("section table runs past the end of the file")
        if xxh3(d[64:table_end]) != table_checksum:
            self.fail("section table checksum mismatch")
        self.sections = [Section(i, struct.unpack_from("<IIQQQQII", d, 64 + 48 * i)) for i in range(nsec)]
        for s in self.sections:
            if s.reserved:
                self.fail("reserved field not 0", s)
            if s.kind not in KINDS and self.minor <= MINOR:
                self.fail(f"unknown section kind {s.kind}", s)
            if s.codec not in CODECS:
                self.fail(f"unknown codec {s.codec}", s)
            if s.codec == DRACO and (s.kind != GEOMETRY or s.count != 1):
                self.fail("codec 2 (Draco) is only for a geometry section of count 1", s)
            if s.offset % 16 or s.offset < table_end:
                self.fail(f"offset {s.offset} not a multiple of 16 after the table", s)
            if s.offset + s.stored_size + 16 > file_size:
                self.fail("section and its 16 bytes of padding run past the end of the file", s)
            if s.codec == RAW and s.raw_size != s.stored_size:
                self.fail("raw codec but raw_size != stored_size", s)
            # Bound what decoding allocates (section 5) before allocating anything.
            if s.raw_size > 1 << 40 or (s.codec != RAW and s.raw_size > 32768 * s.stored_size + MiB):
                self.fail(f"raw_size {s.raw_size} too large for stored_size {s.stored_size}", s)
            if s.kind in KINDS and s.kind not in (GEOMETRY, TEXELS) and s.kind in self.sections_of:
                self.fail(f"second '{s.name}' section", s)
            self.sections_of.setdefault(s.kind, []).append(s)
        if sum(s.raw_size for s in self.sections) > 32768 * file_size + 64 * MiB:
            self.fail("sections together decode to more than 32768 * file_size + 64 MiB")
        # Section 5: no overlap, each section followed by 16 or more zero bytes, and every
        # byte outside header, table and sections zero. The order of sections is free.
        end, previous = table_end, None
        for s in sorted(self.sections, key=lambda s: s.offset) + [None]:
            start = s.offset if s else len(d)
            if s and start < end + (16 if previous else 0):
                self.fail("overlaps the previous section or its 16 bytes of padding", s)
            if any(d[end:start]):
                self.fail(f"non-zero padding (bytes {end} to {start})", previous)
            end, previous = start + (s.stored_size if s else 0), s

    def decode(self, s):
        stored = memoryview(self.data)[s.offset:s.offset + s.stored_size]
        try:
            if s.codec == ZSTD:
                s.raw = self.decode_frames(s, stored)
            elif s.codec == RAW:
                chunks = b"".join(struct.pack("<Q", xxh3(stored[at:at + CHUNK_SIZE]))
                                  for at in range(0, s.stored_size, CHUNK_SIZE))
                if xxh3(chunks) != s.checksum:
                    self.fail("checksum mismatch", s)
                s.raw = bytes(stored)
            elif xxh3(stored) != s.checksum:
                self.fail("checksum mismatch", s)
            elif bytes(stored[:7]) != b"DRACO\x02\x02":  # magic and bitstream version
                self.fail("not a Draco 2.2 stream", s)
        except CodecError as e:
            self.fail(str(e), s)

    def decode_frames(self, s, stored):
        if s.stored_size < 16:
            self.fail("no frame index header", s)
        frame_size, flags, reserved = struct.unpack_from("<IIQ", stored, 0)
        if frame_size < 64 * 1024 or frame_size > 16 * MiB or frame_size & (frame_size - 1):
            self.fail(f"frame size {frame_size} is not a power of two from 64 KiB to 16 MiB", s)
        if flags & ~1 or reserved:
            self.fail("unknown frame flags or reserved bits set", s)
        n = -(-s.raw_size // frame_size)
        index = 16 + 16 * n
        if index > s.stored_size:
            self.fail(f"frame index of {n} entries does not fit", s)
        if xxh3(stored[:index]) != s.checksum:
            self.fail("checksum mismatch (frame index)", s)
        s.frame_size, s.shuffled = frame_size, bool(flags & 1)
        raw = bytearray(s.raw_size)
        pos = index
        for i in range(n):
            size, reserved, checksum = struct.unpack_from("<IIQ", stored, 16 + 16 * i)
            if reserved or size < 1 or pos + size > s.stored_size:
                self.fail(f"frame {i}: bad index entry", s)
            frame = stored[pos:pos + size]
            if xxh3(frame) != checksum:
                self.fail(f"frame {i}: checksum mismatch", s)
            try:
                block = zstd_frame(frame, min(frame_size, s.raw_size - i * frame_size))
                if s.shuffled:
                    unshuffle(block, raw, i * frame_size)
                else:
                    raw[i * frame_size:i * frame_size + len(block)] = block
            except CodecError as e:
                self.fail(f"frame {i}: {e}", s)
            s.frames.append(size)
            pos += size
        if pos != s.stored_size:
            self.fail(f"{s.stored_size - pos} bytes after the last frame", s)
        return raw

    # ------------------------------------------------------------ records

    def records(self, kind, record_type=None):
        s = self.sections_of.get(kind)
        if not s:
            return []
        rows = struct.iter_unpack(ARRAYS[kind][2], s[0].raw)
        return [record_type._make(r) for r in rows] if record_type else list(rows)

    def read_records(self):
        scene = self.sections_of.get(SCENE)
        if not scene:
            self.fail("no scene section")
        if scene[0].count != 1 or scene[0].raw_size != 112:
            self.fail("must hold one 112-byte SceneRecord", scene[0])
        fields = struct.unpack_from("<24I4I", scene[0].raw)
        if any(fields[24:]):
            self.fail("SceneRecord reserved not 0", SCENE)
        self.scene = dict(zip(SCENE_FIELDS, fields))
        self.counts = {k: v for k, v in self.scene.items() if k.startswith("num_")}
        # Geometry and texels counts are not checked: readers go by the mesh and image records.
        for kind, (count, size, _) in ARRAYS.items():
            self.check_section_count(kind, self.counts[count], size)
        self.check_section_count(STRINGS, self.counts["num_strings"])
        self.read_strings()
        self.read_entities()
        self.transforms = [(t[0:16], t[16:32], t[32], t[33]) for t in self.records(TRANSFORMS)]
        self.read_scene_objects()
        self.read_meshes()
        self.read_images()
        self.read_provenance()
        for e, (cat, typ, _, _) in enumerate(self.entities):
            name = self.schema.types[cat][typ][0]
            if name == "fourier" and cat == self.schema.category["material"]:
                self.check_fourier(e)
            elif name == "curve" and cat == self.schema.category["shape"]:
                self.check_curve(e)
            elif name == "heterogeneous" and cat == self.schema.category["medium"]:
                self.check_density(e)
            elif (name in ("subsurface", "kdsubsurface") and cat == self.schema.category["material"]
                  and self.minor >= 1):
                self.check_bssrdf(e)

    def check_section_count(self, kind, count, element_size=None):
        s = self.sections_of.get(kind)
        if not s:
            if count:
                self.fail(f"no '{KINDS[kind]}' section but the SceneRecord counts {count}")
        elif s[0].count != count:
            self.fail(f"count {s[0].count} but the SceneRecord counts {count}", s[0])
        elif element_size and s[0].raw_size != count * element_size:
            self.fail(f"raw_size {s[0].raw_size}, expected {count} * {element_size}", s[0])

    def read_string_table(self, raw, pos, count, where):
        """Strings (section 6); the table must end the section, and string 0 is empty."""
        if pos + 4 * (count + 1) > len(raw):
            self.fail("string offsets run past the section", where)
        offsets = struct.unpack_from(f"<{count + 1}I", raw, pos)
        pos += 4 * (count + 1)
        if offsets[0] != 0 or any(b < a for a, b in zip(offsets, offsets[1:])):
            self.fail("string offsets not non-decreasing from 0", where)
        if pos + offsets[-1] != len(raw):
            self.fail(f"string data ({offsets[-1]} bytes) does not end the section", where)
        if count == 0 or offsets[1] != 0:
            self.fail("string 0 is not the empty string", where)
        data = bytes(raw[pos:])
        # Strings are only printed: readers do not check their UTF-8.
        return [data[a:b].decode("utf-8", "replace") for a, b in zip(offsets, offsets[1:])]

    def read_strings(self):
        s = self.sections_of.get(STRINGS, [None])[0]
        self.strings = []
        if not s:
            self.fail("no strings section")  # section 10: it must exist
        if len(s.raw) < 4 or struct.unpack_from("<I", s.raw)[0] != s.count:
            self.fail("string count differs from the section's count", s)
        # Names and file names the archive does not keep are string 0, read as "".
        self.strings = self.read_string_table(s.raw, 4, s.count, s)

    def read_entities(self):
        schema, n_values = self.schema, self.counts["num_values"]
        self.entities = []
        for i, (cat, reserved, typ, first, count, reserved2) in enumerate(self.records(ENTITIES)):
            if reserved or reserved2:
                self.fail(f"entity {i}: reserved not 0", ENTITIES)
            if cat >= len(schema.types) or typ >= len(schema.types[cat]):
                self.fail(f"entity {i}: unknown category {cat} type {typ}", ENTITIES)
            known = len(schema.types[cat][typ][1])
            # Same minor: exactly the schema's parameters; a newer minor may append some.
            if self.minor == MINOR and count != known or self.minor > MINOR and count < known:
                self.fail(f"entity {i}: {count} values for {known} parameters", ENTITIES)
            if first + count > n_values:
                self.fail(f"entity {i}: values {first}..{first + count} out of range ({n_values})", ENTITIES)
            self.entities.append((cat, typ, first, count))
        self.values = self.records(VALUES)
        self.words = array.array("I", self.sections_of[WORDS][0].raw if WORDS in self.sections_of else b"")
        if sys.byteorder == "big":
            self.words.byteswap()

    def check_values(self):
        """Every value of every entity against its schema parameter (needs the textures)."""
        values, words, n_words, n_strings = self.values, self.words, len(self.words), len(self.strings)
        textures, entities = self.textures, self.entities
        tex_class = {"float texture": self.schema.category["float texture"],
                     "spectrum texture": self.schema.category["spectrum texture"]}
        for e, (cat, typ, first, count) in enumerate(entities):
            tname, params = self.schema.types[cat][typ]
            for j, p in enumerate(params[:count]):
                offset, n, texture, flags = values[first + j]
                where = f"value {first + j} ({tname} {p.name})"
                if flags & ~1:
                    self.fail(f"{where}: reserved flag bits {flags:#x}", VALUES)
                if p.arity and n not in (0, p.arity):
                    self.fail(f"{where}: count {n}, arity {p.arity}", VALUES)
                end = offset + n * WORDS_PER_ELEMENT[p.kind]
                if end > n_words:
                    self.fail(f"{where}: words {offset}..{end} out of range ({n_words})", VALUES)
                if texture != NONE:
                    if p.kind not in tex_class:
                        self.fail(f"{where}: texture {texture} on a {p.kind} parameter", VALUES)
                    self.check_index(texture, len(textures), f"{where}: texture", VALUES)
                    if entities[textures[texture].entity][0] != tex_class[p.kind]:
                        self.fail(f"{where}: texture {texture} is not a {p.kind}", VALUES)
                if p.kind == "string" and any(w >= n_strings for w in words[offset:end]):
                    self.fail(f"{where}: string out of range ({n_strings})", VALUES)

    def expect_category(self, entity, category, what, where):
        cats = (category,) if isinstance(category, str) else category
        if self.schema.category_names[self.entities[entity][0]] not in cats:
            self.fail(f"{what}: entity {entity} is not a {' or '.join(cats)}", where)

    def read_scene_objects(self):
        n, ne, nt = self.counts, len(self.entities), len(self.transforms)
        sc = self.scene
        for field, category in (("camera", "camera"), ("film", "film"), ("filter", "filter"),
                                ("sampler", "sampler"), ("integrator", "integrator"),
                                ("accelerator", "accelerator")):
            self.check_index(sc[field], ne, field, SCENE)
            self.expect_category(sc[field], category, field, SCENE)
        self.check_index(sc["camera_transform"], nt, "camera_transform", SCENE)
        self.check_index(sc["camera_medium"], n["num_media"], "camera_medium", SCENE, True)

        def entity(rec, i, what, kind, category):
            self.check_index(rec.entity, ne, f"{what} {i} entity", kind)
            self.expect_category(rec.entity, category, f"{what} {i}", kind)

        self.textures = self.records(TEXTURES, Texture)
        for i, t in enumerate(self.textures):
            entity(t, i, "texture", TEXTURES, ("float texture", "spectrum texture"))
            if t.reserved:
                self.fail(f"texture {i}: reserved not 0", TEXTURES)
            self.check_index(t.transform, nt, f"texture {i} transform", TEXTURES)
            self.check_index(t.image, n["num_images"], f"texture {i} image", TEXTURES, True)
        self.materials = self.records(MATERIALS, Material)
        for i, m in enumerate(self.materials):
            entity(m, i, "material", MATERIALS, "material")
            if m.reserved:
                self.fail(f"material {i}: reserved not 0", MATERIALS)
            # Range-checked whatever the type (ARCHIVE.md section 7), NONE allowed.
            self.check_index(m.mix0, len(self.materials), f"material {i} mix[0]", MATERIALS, True)
            self.check_index(m.mix1, len(self.materials), f"material {i} mix[1]", MATERIALS, True)
        self.media = self.records(MEDIA, Medium)
        for i, m in enumerate(self.media):
            entity(m, i, "medium", MEDIA, "medium")
            if m.reserved0 or m.reserved1:
                self.fail(f"medium {i}: reserved not 0", MEDIA)
            self.check_index(m.transform, nt, f"medium {i} transform", MEDIA)
        self.lights = self.records(LIGHTS, Light)
        for i, l in enumerate(self.lights):
            entity(l, i, "light", LIGHTS, "light")
            self.check_index(l.transform, nt, f"light {i} transform", LIGHTS)
            self.check_index(l.medium, n["num_media"], f"light {i} medium", LIGHTS, True)
            self.check_index(l.image, n["num_images"], f"light {i} image", LIGHTS, True)
        self.area_lights = [a for (a,) in self.records(AREA_LIGHTS)]
        for i, a in enumerate(self.area_lights):
            self.check_index(a, ne, f"area light {i} entity", AREA_LIGHTS)
            self.expect_category(a, "area light", f"area light {i}", AREA_LIGHTS)
        self.check_values()
        self.shapes = self.records(SHAPES, Shape)
        shape_cat, n_media = self.schema.category["shape"], n["num_media"]
        for i, s in enumerate(self.shapes):
            self.check_index(s.entity, ne, f"shape {i} entity", SHAPES)
            if self.entities[s.entity][0] != shape_cat:
                self.fail(f"shape {i}: entity {s.entity} is not a shape", SHAPES)
            if s.reserved or s.flags & ~3:
                self.fail(f"shape {i}: reserved bits not 0", SHAPES)
            self.check_index(s.mesh, n["num_meshes"], f"shape {i} mesh", SHAPES, True)
            self.check_index(s.material, n["num_materials"], f"shape {i} material", SHAPES)
            self.check_index(s.area_light, n["num_area_lights"], f"shape {i} area_light", SHAPES, True)
            self.check_index(s.inside_medium, n_media, f"shape {i} inside_medium", SHAPES, True)
            self.check_index(s.outside_medium, n_media, f"shape {i} outside_medium", SHAPES, True)
            self.check_index(s.transform, nt, f"shape {i} transform", SHAPES)
            self.check_index(s.object, n["num_objects"], f"shape {i} object", SHAPES, True)
        self.object_shapes = [x for (x,) in self.records(OBJECT_SHAPES)]
        for i, x in enumerate(self.object_shapes):
            self.check_index(x, len(self.shapes), f"object_shapes[{i}]", OBJECT_SHAPES)
        self.objects = self.records(OBJECTS, Object)
        for i, o in enumerate(self.objects):
            if o.reserved:
                self.fail(f"object {i}: reserved not 0", OBJECTS)
            if o.first_shape + o.num_shapes > len(self.object_shapes):
                self.fail(f"object {i}: shapes {o.first_shape}..{o.first_shape + o.num_shapes} "
                          f"out of range ({len(self.object_shapes)})", OBJECTS)
        self.instances = self.records(INSTANCES, Instance)
        for i, o in enumerate(self.instances):
            if o.reserved:
                self.fail(f"instance {i}: reserved not 0", INSTANCES)
            self.check_index(o.object, len(self.objects), f"instance {i} object", INSTANCES)
            self.check_index(o.transform, nt, f"instance {i} transform", INSTANCES)

    def read_meshes(self):
        # Arrays may overlap, and neither the bytes between them nor those after the last are
        # checked: every array is only read, inside its section, and the checksum covers the rest.
        self.meshes = self.records(MESHES, Mesh)
        draco_owner = {}  # a Draco section holds one mesh: its record is the only one naming it
        for i, m in enumerate(self.meshes):
            if m.flags & ~0xF:
                self.fail(f"mesh {i}: unknown flag bits {m.flags:#x}", MESHES)
            self.check_index(m.source_shape, len(self.shapes), f"mesh {i} source_shape", MESHES, True)
            if m.section >= len(self.sections) or self.sections[m.section].kind != GEOMETRY:
                self.fail(f"mesh {i}: section {m.section} is not a geometry section", MESHES)
            g = self.sections[m.section]
            layout_end = 0  # where each array would start in a Draco section's decoded layout
            for field, flag, size, per_triangle in MESH_ARRAYS:
                offset = getattr(m, field)
                if flag is not None and not m.flags & flag:
                    if offset:
                        self.fail(f"mesh {i}: absent {field} at offset {offset}", MESHES)
                    continue
                end = offset + size * (m.num_triangles if per_triangle else m.num_vertices)
                if offset % 16 or end > g.raw_size:
                    self.fail(f"mesh {i}: {field} [{offset}, {end}) misaligned or outside "
                              f"section #{g.index} ({g.raw_size} bytes)", MESHES)
                if g.codec == DRACO:
                    if field == "tangents" or offset != align16(layout_end):
                        self.fail(f"mesh {i}: {field} at {offset} breaks the Draco layout", MESHES)
                    layout_end = end
            if g.codec == DRACO:
                if layout_end != g.raw_size:
                    self.fail(f"raw_size {g.raw_size} but mesh {i}'s arrays end at {layout_end}", g)
                if m.section in draco_owner:
                    self.fail(f"mesh {i}: Draco section #{m.section} holds mesh "
                              f"{draco_owner[m.section]} already", MESHES)
                draco_owner[m.section] = i
                # Not decoded: its counts and triangle indices cannot be checked.
                continue
            if m.num_triangles:
                indices = array.array("I", g.raw[m.indices:m.indices + 12 * m.num_triangles])
                if sys.byteorder == "big":
                    indices.byteswap()
                if max(indices) >= m.num_vertices:
                    self.fail(f"mesh {i}: triangle index {max(indices)} >= {m.num_vertices} vertices", MESHES)

    def read_images(self):
        self.images = self.records(IMAGES, Image)
        n = len(self.images)
        named = {t.image for t in self.textures} | {l.image for l in self.lights}
        for i, im in enumerate(self.images):
            where = f"image {i}"
            if im.r0 or im.r1 or im.r2:
                self.fail(f"{where}: reserved not 0", IMAGES)
            if im.channels not in (1, 3) or im.format not in TEXEL_BYTES or im.wrap not in (0, 1, 2):
                self.fail(f"{where}: channels {im.channels}, format {im.format}, wrap {im.wrap}", IMAGES)
            if not 1 <= im.levels <= 32 or 0 in (im.width, im.height, im.source_width, im.source_height):
                self.fail(f"{where}: {im.levels} levels, {im.width}x{im.height} "
                          f"from {im.source_width}x{im.source_height}", IMAGES)
            if im.section >= len(self.sections) or self.sections[im.section].kind != TEXELS:
                self.fail(f"{where}: section {im.section} is not a texels section", IMAGES)
            offset = im.offset
            for k in range(im.levels):
                texels = max(1, im.width >> k) * max(1, im.height >> k) * im.channels
                end = offset + texels * TEXEL_BYTES[im.format]
                if offset % 16 or end > self.sections[im.section].raw_size:
                    self.fail(f"{where}: level {k} misaligned or outside section #{im.section}", IMAGES)
                offset = align16(end)
            if i in named and im.levels != max(im.width, im.height).bit_length():
                self.fail(f"{where}: {im.levels} levels for {im.width}x{im.height}, "
                          f"expected the whole pyramid", IMAGES)
            if im.distribution != NONE:
                self.check_index(im.distribution, n, f"{where} distribution", IMAGES)
                dist = self.images[im.distribution]
                if dist.format != 0 or dist.levels != 1:
                    self.fail(f"{where}: distribution {im.distribution} not f32 with one level", IMAGES)
            if im.source_image != NONE:
                if (im.width, im.height) == (im.source_width, im.source_height):
                    self.fail(f"{where}: level 0 is the source size, yet it names a source image", IMAGES)
                self.check_index(im.source_image, n, f"{where} source_image", IMAGES)
                src = self.images[im.source_image]
                if (im.source_image == i or src.levels != 1
                        or (src.width, src.height) != (im.source_width, im.source_height)
                        or (src.channels, src.format, src.wrap) != (im.channels, im.format, im.wrap)
                        or src.source_image != NONE):
                    self.fail(f"{where}: source_image {im.source_image} does not match", IMAGES)

    def read_provenance(self):
        s = self.sections_of.get(PROVENANCE, [None])[0]
        if not s:
            self.fail("no provenance section")  # it holds a record for every entity
        if len(s.raw) < 8:
            self.fail("too short", s)
        n, n_strings = struct.unpack_from("<II", s.raw)
        if n != s.count or n_strings < 1 or 8 + 16 * n > len(s.raw):
            self.fail(f"{n} records, {n_strings} strings in a section counting {s.count}", s)
        self.provenance = list(struct.iter_unpack("<4I", s.raw[8:8 + 16 * n]))
        self.provenance_strings = self.read_string_table(s.raw, 8 + 16 * n, n_strings, s)
        for i, (file, _, name, path) in enumerate(self.provenance):
            if max(file, name, path) >= n_strings:
                self.fail(f"record {i}: string out of range ({n_strings})", s)
        need = len(self.entities) + len(self.objects) + len(self.instances)
        if n < need:
            self.fail(f"{n} records, expected at least {need}", s)
        for i, o in enumerate(self.objects):
            self.check_index(o.provenance, len(self.provenance), f"object {i} provenance", OBJECTS)
        for i, o in enumerate(self.instances):
            self.check_index(o.provenance, len(self.provenance), f"instance {i} provenance", INSTANCES)

    # ------------------------------------------------------------ parameters

    def type_name(self, entity):
        cat, typ, _, _ = self.entities[entity]
        return self.schema.types[cat][typ][0]

    def param(self, entity, j):
        """(Param, value record or None when the entity lacks it: an older minor)."""
        cat, typ, first, count = self.entities[entity]
        p = self.schema.types[cat][typ][1][j]
        return p, (self.values[first + j] if j < count else None)

    def decode_words(self, p, offset, count):
        words = self.words[offset:offset + count * WORDS_PER_ELEMENT[p.kind]]
        if p.kind in ("int", "bool"):
            return list(struct.unpack(f"<{len(words)}i", words.tobytes()))
        if p.kind == "string":
            return [self.strings[w] for w in words]
        return list(struct.unpack(f"<{len(words)}f", words.tobytes()))

    def value(self, entity, name):
        """A parameter's values; count 0 or a missing value means the schema default."""
        cat, typ, _, _ = self.entities[entity]
        j = [p.name for p in self.schema.types[cat][typ][1]].index(name)
        p, v = self.param(entity, j)
        return self.decode_words(p, v[0], v[1]) if v and v[1] else parse_default(p)

    def check_fourier(self, e):
        """ARCHIVE.md section 10's rules for the table, when present."""
        mu = self.value(e, "bsdfmu")
        if not mu:
            return  # no zenith nodes, no table (archives before 1.1 lack the parameters altogether)
        scalar = lambda name: (self.value(e, name) or [math.nan])[0]
        eta, mmax, channels = scalar("bsdfeta"), scalar("bsdfmmax"), scalar("bsdfchannels")
        cdf, offsets, coeffs = (self.value(e, name) for name in ("bsdfcdf", "bsdfoffsets", "bsdfcoeffs"))
        nodes = len(mu)
        if not (2 <= nodes <= 1024 and len(cdf) == nodes * nodes and len(offsets) == 2 * nodes * nodes
                and all(-1 <= a <= b <= 1 for a, b in zip(mu, mu[1:])) and mu[-2] != mu[-1]
                and channels in (1, 3) and 0 <= mmax <= 2048 and eta > 0
                and all(math.isfinite(x) for x in (eta, *mu, *cdf, *coeffs))
                and all(0 <= m <= mmax and 0 <= off and off + channels * m <= len(coeffs)
                        for off, m in zip(offsets[::2], offsets[1::2]))):
            self.fail(f"entity {e}: inconsistent fourier table", VALUES)

    def check_bssrdf(self, e):
        """ARCHIVE.md section 10's rules for a subsurface material's profile table (2.1)."""
        rho, radius, profile, rho_eff, cdf = (
            self.value(e, name) or [] for name in
            ("bssrdfrho", "bssrdfradius", "bssrdfprofile", "bssrdfrhoeff", "bssrdfcdf"))
        n, m = len(rho), len(radius)
        increasing = lambda xs: all(a < b for a, b in zip(xs, xs[1:]))
        if not (4 <= n <= 4096 and 4 <= m <= 4096 and len(profile) == n * m and len(cdf) == n * m
                and len(rho_eff) == n and increasing(rho) and 0 <= rho[0] and rho[-1] <= 1
                and increasing(radius) and radius[0] == 0
                and all(math.isfinite(x) for x in (*rho, *radius, *profile, *rho_eff, *cdf))
                and all(x >= 0 for x in (*profile, *rho_eff))):
            self.fail(f"entity {e}: inconsistent BSSRDF table", VALUES)

    def check_curve(self, e):
        """ARCHIVE.md section 10's rules for a curve's counts."""
        degree, basis, kind = (self.value(e, name)[0] for name in ("degree", "basis", "type"))
        points, normals = len(self.value(e, "P")) // 3, len(self.value(e, "N")) // 3
        ok = degree in (2, 3) and basis in ("bezier", "bspline") and kind in ("flat", "ribbon", "cylinder")
        if ok and basis == "bezier":
            ok, segments = (points - 1 - degree) % degree == 0, (points - 1) // degree
        elif ok:
            ok, segments = points >= degree + 1, points - degree
        if ok and kind == "ribbon":
            j = [p.name for p in self.schema.types[self.entities[e][0]][self.entities[e][1]][1]].index("N")
            _, v = self.param(e, j)
            ok = normals == segments + 1 and v is not None and v[3] & 1  # given by the scene
        if not ok:
            self.fail(f"entity {e}: curve counts break the rules", VALUES)

    def check_density(self, e):
        """ARCHIVE.md section 10: a heterogeneous medium has nx * ny * nz density values."""
        nx, ny, nz = (self.value(e, name)[0] for name in ("nx", "ny", "nz"))
        if len(self.value(e, "density")) != nx * ny * nz:
            self.fail(f"entity {e}: density grid is not nx * ny * nz", VALUES)

    # ------------------------------------------------------------ output

    def summary(self):
        """The archive described in the layout of `pbrtc --info`."""
        n, sc = self.counts, self.scene
        effects = [name for bit, name in enumerate(EFFECTS) if self.effects >> bit & 1]  # others ignored
        out = [f"{self.path}: pbrtc scene archive {self.major}.{self.minor}, {fmt_size(len(self.data))}",
               f"  effects: {', '.join(effects) or 'none'}",
               f"  camera {self.type_name(sc['camera'])}, film {self.value(sc['film'], 'xresolution')[0]}x"
               f"{self.value(sc['film'], 'yresolution')[0]}, sampler {self.type_name(sc['sampler'])}, "
               f"integrator {self.type_name(sc['integrator'])}",
               f"  shapes {n['num_shapes']} (meshes {n['num_meshes']}, triangles {self.triangles()}), "
               f"lights {n['num_lights']}, area lights {n['num_area_lights']}, materials {n['num_materials']}, "
               f"textures {n['num_textures']}, media {n['num_media']}, objects {n['num_objects']}, "
               f"instances {n['num_instances']}, images {n['num_images']}",
               f"  entities {n['num_entities']}, values {n['num_values']}, "
               f"transforms {n['num_transforms']}, strings {n['num_strings']}",
               "  sections:",
               f"  {'#':>5}  {'kind':<14} {'codec':<5} {'count':>8} {'raw':>12} {'stored':>12} {'ratio':>7}"]
        raw = sum(s.raw_size for s in self.sections)
        stored = sum(s.stored_size for s in self.sections)
        ratio = lambda st, r: f"{100.0 * st / r:.1f}%" if r else "-"
        for s in self.sections:
            out.append(f"  {s.index:>5}  {KINDS.get(s.kind, 'unknown'):<14} {CODECS[s.codec]:<5} {s.count:>8}"
                       f" {fmt_size(s.raw_size):>12} {fmt_size(s.stored_size):>12}"
                       f" {ratio(s.stored_size, s.raw_size):>7}")
        out.append(f"  {'':>5}  {'total':<14} {'':<5} {'':>8} {fmt_size(raw):>12} {fmt_size(stored):>12}"
                   f" {ratio(stored, raw):>7}")
        return out

    def triangles(self):
        return sum(m.num_triangles for m in self.meshes)

    def where(self, record):
        if record >= len(self.provenance):
            return ""
        file, line, name, path = self.provenance[record]
        ps = self.provenance_strings
        return (f"  @ {ps[file] or '?'}:{line}" + (f" name={ps[name]!r}" if name else "")
                + (f" path={ps[path]!r}" if path else ""))

    def describe(self, e, max_elements=6):
        """An entity's parameters; `~` marks those not given in the scene."""
        cat, typ, _, count = self.entities[e]
        parts = []
        for j, p in enumerate(self.schema.types[cat][typ][1]):
            _, v = self.param(e, j)
            given = v is not None and v[3] & 1
            if v is not None and v[2] != NONE:
                text = f"tex#{v[2]}"
            elif not given and p.flags.startswith("computed: "):  # the placeholder is not the value
                text = f"({p.flags[10:].rstrip('; ')})"
            elif v is None or v[1] == 0:
                text = f"default {p.default}" if parse_default(p) else "[]"
            else:
                vals = self.decode_words(p, v[0], v[1])
                shown = vals[:max_elements * WORDS_PER_ELEMENT[p.kind]]
                text = " ".join(repr(x) if p.kind == "string" else f"{x:g}" for x in shown)
                if len(shown) < len(vals):
                    text += " ..."
                if v[1] != 1:
                    text = f"[{v[1]}] {text}"
            parts.append(f"{p.name}{'' if given else '~'}={text}")
        return f"{self.schema.category_names[cat]} {self.type_name(e)}: " + ", ".join(parts)

    def details(self, limit=20):
        """The records read, `limit` of each kind at most."""
        out = []
        opt = lambda x: "-" if x == NONE else x
        animated = lambda t: self.transforms[t][0] != self.transforms[t][1]

        def listing(name, records, describe):
            out.extend(f"  {name} {i}: {describe(r)}" for i, r in enumerate(records[:limit]))
            if len(records) > limit:
                out.append(f"  ... {len(records) - limit} more {name} records")

        for s in self.sections:
            if s.codec == ZSTD:
                out.append(f"  section #{s.index} {s.name}: zstd, {len(s.frames)} frames of "
                           f"{s.frame_size} bytes, {'shuffled' if s.shuffled else 'plain'}, stored "
                           f"in {s.frames[:4]}{' ...' if len(s.frames) > 4 else ''} bytes")
            elif s.codec == DRACO:
                out.append(f"  section #{s.index} {s.name}: Draco stream, not decoded")
        for field in ("camera", "film", "sampler", "integrator", "filter", "accelerator"):
            out.append(f"  {field}: {self.describe(self.scene[field])}{self.where(self.scene[field])}")
        start, end, t0, t1 = self.transforms[self.scene["camera_transform"]]
        out.append(f"  camera transform: animated={start != end} t=[{t0:g},{t1:g}] "
                   f"row0={[f'{x:g}' for x in start[:4]]}")
        listing("material", self.materials, lambda m: self.describe(m.entity) + (
            f" mix={m.mix0},{m.mix1}" if self.type_name(m.entity) == "mix" else "") + self.where(m.entity))
        listing("texture", self.textures,
                lambda t: f"{self.describe(t.entity)} image={opt(t.image)}{self.where(t.entity)}")
        listing("medium", self.media, lambda m: self.describe(m.entity) + self.where(m.entity))
        listing("light", self.lights, lambda l: f"{self.describe(l.entity)} medium={opt(l.medium)} "
                                                f"image={opt(l.image)}{self.where(l.entity)}")
        listing("area light", self.area_lights, lambda a: self.describe(a) + self.where(a))

        def shape(s):
            mesh = ""
            if s.mesh != NONE:
                m = self.meshes[s.mesh]
                mesh = (f" mesh={s.mesh}(v={m.num_vertices} t={m.num_triangles} flags={m.flags:#x} "
                        f"sec=#{m.section} refine={m.refine_level} src={opt(m.source_shape)})")
            return (f"{self.describe(s.entity, 3)}{mesh} mat={s.material} al={opt(s.area_light)} "
                    f"media={opt(s.inside_medium)},{opt(s.outside_medium)} xf={s.transform}"
                    f"{'(animated)' if animated(s.transform) else ''} obj={opt(s.object)} "
                    f"flags={s.flags}{self.where(s.entity)}")
        listing("shape", self.shapes, shape)
        listing("object", self.objects, lambda o: "shapes "
                f"{self.object_shapes[o.first_shape:][:min(o.num_shapes, limit)]}{self.where(o.provenance)}")
        listing("instance", self.instances, lambda o: f"object {o.object} xf={o.transform} translate=("
                + ",".join(f"{self.transforms[o.transform][0][k]:g}" for k in (3, 7, 11)) + ")"
                + self.where(o.provenance))
        listing("image", self.images, lambda im: (
            f"{im.width}x{im.height}x{im.channels} levels={im.levels} format={im.format} sec=#{im.section} "
            f"offset={im.offset} wrap={im.wrap} distribution={opt(im.distribution)} "
            f"source={im.source_width}x{im.source_height} source_image={opt(im.source_image)}"))
        moving = [(i, t) for i, t in enumerate(self.transforms) if t[0] != t[1]]
        listing("animated transform", moving, lambda it: (
            f"#{it[0]} t=[{it[1][2]:g},{it[1][3]:g}] translate "
            + " -> ".join("(" + ",".join(f"{m[k]:g}" for k in (3, 7, 11)) + ")" for m in it[1][:2])))
        return out


class ReaderCrash(Exception):
    """An exception none of the reader's own checks raised: a check it lacks, or a bug."""


def check_file(path, schema, pbrtc, verbose):
    """Print what -v asks for and the file's verdict; return True if it is ok, False if the
    reader refused it with one of its own errors. Any other exception is the reader's failure,
    not a verdict on the file: it raises ReaderCrash, so a damaged archive that crashes the reader
    never counts as correctly refused."""
    try:
        a = Archive(path, schema)
        a.read()
        summary = a.summary()
        if verbose:
            print("\n".join(summary + a.details()))
    except ArchiveError as e:
        print(f"{path}: error: {e}")
        return False
    except OSError as e:
        print(f"{path}: error: cannot read: {e.strerror}")
        return False
    except Exception as e:
        raise ReaderCrash(f"{path}: reader crashed: {type(e).__name__}: {e}") from e
    if pbrtc:
        info = subprocess.run([pbrtc, "--info", path], capture_output=True, text=True)
        if info.returncode:
            print(f"{path}: error: `pbrtc --info` failed: {info.stderr.strip()}")
            return False
        diff = list(difflib.unified_diff(info.stdout.splitlines(), summary, "pbrtc --info", "read_pbrta.py",
                                         lineterm=""))
        if diff:
            print("\n".join(diff))
            print(f"{path}: error: summary differs from `pbrtc --info`")
            return False
    print(f"{path}: ok ({len(a.sections)} sections, {len(a.entities)} entities, "
          f"{a.triangles()} triangles, {len(a.images)} images)")
    return True


def main():
    ap = argparse.ArgumentParser(description="Read and check pbrtc scene archives from the spec alone.")
    ap.add_argument("--schema", required=True, help="format/SCHEMA.md")
    ap.add_argument("--pbrtc", help="compare with `PBRTC --info FILE`")
    ap.add_argument("-v", "--verbose", action="store_true", help="print the summary and the records read")
    ap.add_argument("files", nargs="+", metavar="FILE.pbrta")
    args = ap.parse_args()
    if args.pbrtc and not shutil.which(args.pbrtc):
        ap.error(f"cannot run {args.pbrtc}")
    try:
        schema = Schema(args.schema)
    except (OSError, ValueError, IndexError) as e:
        ap.error(f"cannot read schema {args.schema}: {e}")
    try:
        ok = [check_file(f, schema, args.pbrtc, args.verbose) for f in args.files]
    except ReaderCrash as e:
        traceback.print_exc()
        print(e)
        return 2
    return 0 if all(ok) else 1


if __name__ == "__main__":
    sys.exit(main())
