//! Gmsh MSH 4.1 reader (ASCII and binary) for mesh import (issue 10).
//!
//! Reads the subset of the format a peridynamic discretisation needs: the
//! `$MeshFormat`, `$PhysicalNames`, `$Entities`, `$Nodes` and `$Elements`
//! sections; every other section (`$Periodic`, `$NodeData`, `$Comments`, ...)
//! is skipped. Each element of the requested dimension becomes one cell with its
//! centroid and its area (2D) or volume (3D); lower-dimensional elements
//! (boundary curves, faces, points) only give physical-group membership.
//!
//! Robustness: the reader never panics and never allocates what a header claims
//! before checking that the remaining bytes can hold it; every count, node tag
//! and element is validated, and errors name the section, the element or node
//! tag and the line (ASCII) or byte offset (binary).
//!
//! Only `std` is used. Supported cells: 2D linear triangles (Gmsh type 2) and
//! quadrangles (3) in the z = 0 plane; 3D linear tetrahedra (4) and hexahedra (5).

use std::collections::{BTreeMap, HashMap};
use std::fmt;

/// A reading error; `message` names what is wrong and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshError {
    pub message: String,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for MeshError {}

fn error<T>(message: impl Into<String>) -> Result<T, MeshError> {
    Err(MeshError {
        message: message.into(),
    })
}

/// The cells (elements of the requested dimension), one entry per cell.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshCells {
    /// 2 or 3.
    pub dim: usize,
    /// Gmsh element tag of each cell (for messages).
    pub element_tag: Vec<u64>,
    /// Area centroid (2D, z = 0) or volume centroid (3D).
    pub centroid: Vec<[f64; 3]>,
    /// Area (2D) or volume (3D), > 0.
    pub measure: Vec<f64>,
    /// Indices into [`Mesh::nodes`] of each cell's nodes, in Gmsh order.
    pub nodes: Vec<Vec<usize>>,
    /// Indices into [`Mesh::groups`] of the physical groups of each cell (those
    /// of its geometric entity; empty when the entity has none).
    pub groups: Vec<Vec<usize>>,
}

/// A physical group. `(dim, tag)` identifies it (Gmsh tags are per dimension).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PhysicalGroup {
    pub dim: usize,
    pub tag: i32,
    /// From `$PhysicalNames`; empty when the group is unnamed.
    pub name: String,
    /// Sorted, distinct indices into [`Mesh::nodes`] of all nodes of the
    /// group's elements (of any dimension).
    pub nodes: Vec<usize>,
    /// Sorted indices into the cells of the cells in this group (empty unless
    /// `dim` is the mesh dimension).
    pub cells: Vec<usize>,
    /// Node indices of the group's elements of dimension `mesh dimension − 1`
    /// (boundary segments in 2D, faces in 3D), for tractions.
    pub facets: Vec<Vec<usize>>,
}

/// A mesh read by [`read_msh`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Node coordinates in `$Nodes` order.
    pub nodes: Vec<[f64; 3]>,
    /// Gmsh tag of each node (tags need not be contiguous).
    pub node_tag: Vec<u64>,
    pub cells: MeshCells,
    /// Every physical group named in `$PhysicalNames` or used by an entity,
    /// sorted by (dim, tag).
    pub groups: Vec<PhysicalGroup>,
}

impl Mesh {
    /// The physical group called `name` (names may repeat across dimensions:
    /// the first, lowest dimension, is returned).
    #[cfg(feature = "fixtures")]
    pub fn group(&self, name: &str) -> Option<&PhysicalGroup> {
        self.groups.iter().find(|g| g.name == name)
    }
}

/// Reads a Gmsh MSH 4.1 file (ASCII or binary, either endianness) and returns
/// its elements of dimension `dim` (2 or 3) as cells.
pub fn read_msh(bytes: &[u8], dim: usize) -> Result<Mesh, MeshError> {
    if dim != 2 && dim != 3 {
        return error(format!("mesh dimension must be 2 or 3, not {dim}"));
    }
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let raw = parse(bytes, dim)?;
    build(raw, dim)
}

// ---------------------------------------------------------------------------
// Element types

/// (name, dimension, number of nodes) of a Gmsh element type.
fn element_type(t: i32) -> Option<(&'static str, usize, usize)> {
    Some(match t {
        1 => ("2-node line", 1, 2),
        2 => ("3-node triangle", 2, 3),
        3 => ("4-node quadrangle", 2, 4),
        4 => ("4-node tetrahedron", 3, 4),
        5 => ("8-node hexahedron", 3, 8),
        6 => ("6-node prism", 3, 6),
        7 => ("5-node pyramid", 3, 5),
        8 => ("3-node line", 1, 3),
        9 => ("6-node triangle", 2, 6),
        10 => ("9-node quadrangle", 2, 9),
        11 => ("10-node tetrahedron", 3, 10),
        12 => ("27-node hexahedron", 3, 27),
        13 => ("18-node prism", 3, 18),
        14 => ("14-node pyramid", 3, 14),
        15 => ("1-node point", 0, 1),
        16 => ("8-node quadrangle", 2, 8),
        17 => ("20-node hexahedron", 3, 20),
        18 => ("15-node prism", 3, 15),
        19 => ("13-node pyramid", 3, 13),
        20 => ("9-node triangle", 2, 9),
        21 => ("10-node triangle", 2, 10),
        22 => ("12-node triangle", 2, 12),
        23 => ("15-node triangle", 2, 15),
        24 => ("15-node triangle (incomplete)", 2, 15),
        25 => ("21-node triangle", 2, 21),
        26 => ("4-node line", 1, 4),
        27 => ("5-node line", 1, 5),
        28 => ("6-node line", 1, 6),
        29 => ("20-node tetrahedron", 3, 20),
        30 => ("35-node tetrahedron", 3, 35),
        31 => ("56-node tetrahedron", 3, 56),
        92 => ("64-node hexahedron", 3, 64),
        93 => ("125-node hexahedron", 3, 125),
        _ => return None,
    })
}

fn supported_cells(dim: usize) -> &'static str {
    if dim == 2 {
        "3-node triangles (type 2) and 4-node quadrangles (type 3)"
    } else {
        "4-node tetrahedra (type 4) and 8-node hexahedra (type 5)"
    }
}

// ---------------------------------------------------------------------------
// Low-level reading

struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    binary: bool,
    big_endian: bool,
    size_t: usize,
    section: &'static str,
}

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | b'\x0b' | b'\x0c')
}

impl<'a> Cursor<'a> {
    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    fn location(&self) -> String {
        if self.binary {
            format!("byte {}", self.pos)
        } else {
            let line = 1 + self.data[..self.pos]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            format!("line {line}")
        }
    }

    fn fail<T>(&self, what: impl fmt::Display) -> Result<T, MeshError> {
        let section = if self.section.is_empty() {
            String::new()
        } else {
            format!("{}: ", self.section)
        };
        error(format!("{section}{what} (at {})", self.location()))
    }

    fn skip_space(&mut self) {
        while self.pos < self.data.len() && is_space(self.data[self.pos]) {
            self.pos += 1;
        }
    }

    /// Next whitespace-delimited ASCII token.
    fn token(&mut self, what: &str) -> Result<&'a str, MeshError> {
        self.skip_space();
        let start = self.pos;
        while self.pos < self.data.len() && !is_space(self.data[self.pos]) {
            self.pos += 1;
        }
        if start == self.pos {
            self.pos = start;
            return self.fail(format!("unexpected end of file, expected {what}"));
        }
        match std::str::from_utf8(&self.data[start..self.pos]) {
            Ok(s) => Ok(s),
            Err(_) => {
                self.pos = start;
                self.fail(format!("expected {what}, found non-text bytes"))
            }
        }
    }

    fn parse_token<T: std::str::FromStr>(
        &mut self,
        what: &str,
        kind: &str,
    ) -> Result<T, MeshError> {
        let start = self.pos;
        let t = self.token(what)?;
        match t.parse::<T>() {
            Ok(v) => Ok(v),
            Err(_) => {
                self.pos = start;
                self.skip_space();
                let shown: String = t.chars().take(40).collect();
                self.fail(format!("expected {what} ({kind}), found \"{shown}\""))
            }
        }
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], MeshError> {
        if self.remaining() < n {
            return self.fail(format!("unexpected end of file, expected {what}"));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn bytes<const N: usize>(&mut self, what: &str) -> Result<[u8; N], MeshError> {
        let s = self.take(N, what)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        if self.big_endian {
            a.reverse();
        }
        Ok(a) // now little-endian
    }

    /// `size_t` value (unsigned).
    fn size(&mut self, what: &str) -> Result<u64, MeshError> {
        if !self.binary {
            return self.parse_token::<u64>(what, "an unsigned integer");
        }
        if self.size_t == 4 {
            Ok(u32::from_le_bytes(self.bytes::<4>(what)?) as u64)
        } else {
            Ok(u64::from_le_bytes(self.bytes::<8>(what)?))
        }
    }

    fn int(&mut self, what: &str) -> Result<i32, MeshError> {
        if !self.binary {
            return self.parse_token::<i32>(what, "an integer");
        }
        Ok(i32::from_le_bytes(self.bytes::<4>(what)?))
    }

    fn float(&mut self, what: &str) -> Result<f64, MeshError> {
        if !self.binary {
            return self.parse_token::<f64>(what, "a number");
        }
        Ok(f64::from_le_bytes(self.bytes::<8>(what)?))
    }

    /// Reads a count and checks that the rest of the file can hold `count`
    /// items of at least `min_bytes` bytes each (binary) or `min_tokens`
    /// tokens each (ASCII, two bytes per token at least), so no allocation or
    /// loop is sized by an unchecked header value.
    fn count(
        &mut self,
        what: &str,
        min_bytes: usize,
        min_tokens: usize,
    ) -> Result<usize, MeshError> {
        let start = self.pos;
        let n = self.size(what)?;
        let each = if self.binary {
            min_bytes
        } else {
            2 * min_tokens
        }
        .max(1) as u64;
        let fits = n
            .checked_mul(each)
            .is_some_and(|b| b <= self.remaining() as u64);
        if !fits {
            self.pos = start;
            self.skip_space();
            return self.fail(format!(
                "{what} is {n}, more than the {} bytes left in the file can hold",
                self.remaining()
            ));
        }
        Ok(n as usize)
    }

    /// Reads the rest of the current line (without its end) and consumes the end.
    fn line(&mut self) -> &'a [u8] {
        let start = self.pos;
        while self.pos < self.data.len() && self.data[self.pos] != b'\n' {
            self.pos += 1;
        }
        let mut l = &self.data[start..self.pos];
        if self.pos < self.data.len() {
            self.pos += 1;
        }
        if let Some(s) = l.strip_suffix(b"\r") {
            l = s;
        }
        l
    }

    /// Next section start line `$Name`; `None` at the end of the file.
    fn section_start(&mut self) -> Result<Option<&'a [u8]>, MeshError> {
        self.skip_space();
        if self.pos == self.data.len() {
            return Ok(None);
        }
        if self.data[self.pos] != b'$' {
            return self.fail("expected a section start such as $Nodes");
        }
        let l = self.line();
        let name = l[1..].trim_ascii_end();
        if name.is_empty() || name.len() > 64 {
            self.pos -= 1;
            return self.fail("malformed section start line");
        }
        Ok(Some(name))
    }

    /// Consumes `$End<name>` (after optional white space) and its line end.
    fn section_end(&mut self, name: &str) -> Result<(), MeshError> {
        self.skip_space();
        let tag = format!("$End{name}");
        let rest = &self.data[self.pos..];
        let ok =
            rest.starts_with(tag.as_bytes()) && rest.get(tag.len()).is_none_or(|&b| is_space(b));
        if !ok {
            return self.fail(format!(
                "expected {tag} (the section holds more or less data than its counts say)"
            ));
        }
        self.pos += tag.len();
        self.line();
        Ok(())
    }

    /// Skips an unknown section up to the line `$End<name>`.
    fn skip_section(&mut self, name: &[u8]) -> Result<(), MeshError> {
        let mut tag = b"\n$End".to_vec();
        tag.extend_from_slice(name);
        let start = self.pos.saturating_sub(1);
        let found = self.data[start..]
            .windows(tag.len())
            .enumerate()
            .find(|(i, w)| {
                *w == &tag[..]
                    && self
                        .data
                        .get(start + i + tag.len())
                        .is_none_or(|&b| is_space(b))
            })
            .map(|(i, _)| start + i);
        match found {
            Some(p) => {
                self.pos = p + tag.len();
                self.line();
                Ok(())
            }
            None => self.fail(format!(
                "section ${} has no $End{} line",
                show(name),
                show(name)
            )),
        }
    }
}

fn show(name: &[u8]) -> String {
    String::from_utf8_lossy(name).chars().take(64).collect()
}

// ---------------------------------------------------------------------------
// Parsing into raw tables

/// Element tag and node tags of a lower-dimensional element.
type LowerElement = (u64, Vec<u64>);

#[derive(Default)]
struct Raw {
    names: BTreeMap<(usize, i32), String>,
    /// (entity dim, entity tag) -> physical tags
    entities: Option<HashMap<(usize, i32), Vec<i32>>>,
    node_tags: Vec<u64>,
    coords: Vec<[f64; 3]>,
    nodes_seen: bool,
    elements_seen: bool,
    /// Cells: element tag, entity tag, type, offset into `cell_nodes`.
    cells: Vec<(u64, i32, i32, usize)>,
    cell_nodes: Vec<u64>,
    /// Lower-dimensional elements: (dim, entity tag) -> (element tag, node tags) of its elements.
    lower: HashMap<(usize, i32), Vec<LowerElement>>,
    /// Element dimensions present (for the "no cells" message).
    dims_present: [usize; 4],
}

fn parse(bytes: &[u8], dim: usize) -> Result<Raw, MeshError> {
    let mut c = Cursor {
        data: bytes,
        pos: 0,
        binary: false,
        big_endian: false,
        size_t: 8,
        section: "",
    };
    let mut raw = Raw::default();
    mesh_format(&mut c)?;
    while let Some(name) = c.section_start()? {
        section(&mut c, name, &mut raw, dim)?;
        c.section = "";
    }
    if !raw.nodes_seen {
        return error("the file has no $Nodes section");
    }
    if !raw.elements_seen {
        return error("the file has no $Elements section");
    }
    Ok(raw)
}

/// `$MeshFormat`: version 4.1, ASCII or binary (with its endianness), the size of `size_t`.
fn mesh_format(c: &mut Cursor) -> Result<(), MeshError> {
    match c.section_start() {
        Ok(Some(b"MeshFormat")) => {}
        _ => {
            c.pos = 0;
            return c.fail("not a Gmsh MSH file: it must start with $MeshFormat");
        }
    }
    c.section = "$MeshFormat";
    let version = c.token("the format version")?;
    if version != "4.1" {
        let v: String = version.chars().take(20).collect();
        return c.fail(format!(
            "MSH version {v} is not supported; save as version 4.1 (Gmsh option Mesh.MshFileVersion = 4.1)"
        ));
    }
    let file_type = c.parse_token::<u32>("the file type", "0 for ASCII, 1 for binary")?;
    let data_size = c.parse_token::<u32>("the data size", "an integer")?;
    if file_type > 1 {
        return c.fail(format!(
            "file type must be 0 (ASCII) or 1 (binary), not {file_type}"
        ));
    }
    if data_size != 4 && data_size != 8 {
        return c.fail(format!(
            "data size (size of size_t) must be 4 or 8, not {data_size}"
        ));
    }
    c.size_t = data_size as usize;
    c.line();
    if file_type == 1 {
        let one = c.take(4, "the binary endianness marker (int 1)")?;
        let one = [one[0], one[1], one[2], one[3]];
        if i32::from_le_bytes(one) == 1 {
            c.big_endian = false;
        } else if i32::from_be_bytes(one) == 1 {
            c.big_endian = true;
        } else {
            return c
                .fail("binary file without the endianness marker (int 1) after the format line");
        }
    }
    c.section_end("MeshFormat")?;
    c.binary = file_type == 1;
    Ok(())
}

/// The section `name` (each read once; unknown sections skipped).
fn section(c: &mut Cursor, name: &[u8], raw: &mut Raw, dim: usize) -> Result<(), MeshError> {
    match name {
        b"PhysicalNames" => {
            c.section = "$PhysicalNames";
            if !raw.names.is_empty() {
                return c.fail("a second $PhysicalNames section");
            }
            physical_names(c, raw)?;
            c.section_end("PhysicalNames")?;
        }
        b"Entities" => {
            c.section = "$Entities";
            if raw.entities.is_some() {
                return c.fail("a second $Entities section");
            }
            raw.entities = Some(entities(c)?);
            c.section_end("Entities")?;
        }
        b"PartitionedEntities" => {
            c.section = "$PartitionedEntities";
            return c.fail("partitioned meshes are not supported; save the mesh unpartitioned");
        }
        b"Nodes" => {
            c.section = "$Nodes";
            if raw.nodes_seen {
                return c.fail("a second $Nodes section");
            }
            raw.nodes_seen = true;
            nodes(c, raw)?;
            c.section_end("Nodes")?;
        }
        b"Elements" => {
            c.section = "$Elements";
            if raw.elements_seen {
                return c.fail("a second $Elements section");
            }
            raw.elements_seen = true;
            elements(c, raw, dim)?;
            c.section_end("Elements")?;
        }
        other => {
            c.section = "";
            c.skip_section(other)?;
        }
    }
    Ok(())
}

/// `$PhysicalNames` (ASCII text in binary files too).
fn physical_names(c: &mut Cursor, raw: &mut Raw) -> Result<(), MeshError> {
    let binary = c.binary;
    c.binary = false;
    let result = (|| {
        let n = c.count("the number of physical names", 0, 3)?;
        for _ in 0..n {
            let d = c.parse_token::<usize>("a physical group dimension", "0 to 3")?;
            if d > 3 {
                return c.fail(format!("physical group dimension {d} (must be 0 to 3)"));
            }
            let tag = c.int("a physical tag")?;
            let line = c.line().trim_ascii();
            let name = match line {
                [b'"', inner @ .., b'"'] => inner,
                _ => {
                    c.pos -= 1;
                    return c.fail(format!(
                        "physical group ({d}, {tag}): its name must be in double quotes"
                    ));
                }
            };
            if raw
                .names
                .insert((d, tag), String::from_utf8_lossy(name).into_owned())
                .is_some()
            {
                return c.fail(format!("physical group ({d}, {tag}) is named twice"));
            }
        }
        Ok(())
    })();
    c.binary = binary;
    result
}

fn entities(c: &mut Cursor) -> Result<HashMap<(usize, i32), Vec<i32>>, MeshError> {
    let mut map = HashMap::new();
    let s = c.size_t;
    let counts = [
        c.count("the number of point entities", 4 + 24 + s, 5)?,
        c.count("the number of curve entities", 4 + 48 + 2 * s, 9)?,
        c.count("the number of surface entities", 4 + 48 + 2 * s, 9)?,
        c.count("the number of volume entities", 4 + 48 + 2 * s, 9)?,
    ];
    let names = ["point", "curve", "surface", "volume"];
    for (d, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.int(&format!("a {} entity tag", names[d]))?;
            for _ in 0..if d == 0 { 3 } else { 6 } {
                c.float("an entity coordinate or bounding box")?;
            }
            let np = c.count(
                &format!("the number of physical tags of {} {tag}", names[d]),
                4,
                1,
            )?;
            let mut phys = Vec::with_capacity(np);
            for _ in 0..np {
                phys.push(c.int("a physical tag")?);
            }
            if d > 0 {
                let nb = c.count(
                    &format!("the number of bounding entities of {} {tag}", names[d]),
                    4,
                    1,
                )?;
                for _ in 0..nb {
                    c.int("a bounding entity tag")?;
                }
            }
            if map.insert((d, tag), phys).is_some() {
                return c.fail(format!("{} entity {tag} is defined twice", names[d]));
            }
        }
    }
    Ok(map)
}

fn nodes(c: &mut Cursor, raw: &mut Raw) -> Result<(), MeshError> {
    let s = c.size_t;
    let blocks = c.count("the number of node blocks", 12 + s, 4)?;
    let total = c.size("the number of nodes")?;
    c.size("the minimum node tag")?;
    c.size("the maximum node tag")?;
    let mut read = 0u64;
    for _ in 0..blocks {
        let edim = c.int("a node block entity dimension")?;
        let etag = c.int("a node block entity tag")?;
        let parametric = c.int("the parametric flag")?;
        if !(0..=3).contains(&edim) || !(0..=1).contains(&parametric) {
            return c.fail(format!(
                "node block of entity ({edim}, {etag}): dimension must be 0 to 3 and the parametric flag 0 or 1 (found {parametric})"
            ));
        }
        let extra = if parametric == 1 { edim as usize } else { 0 };
        let n = c.count(
            &format!("the node count of the block of entity ({edim}, {etag})"),
            s + 8 * (3 + extra),
            4 + extra,
        )?;
        let first = raw.node_tags.len();
        raw.node_tags.reserve(n);
        raw.coords.reserve(n);
        for _ in 0..n {
            let t = c.size("a node tag")?;
            if t == 0 {
                return c.fail("node tag 0 (tags start at 1)");
            }
            raw.node_tags.push(t);
        }
        for i in 0..n {
            let mut x = [0.0; 3];
            for v in &mut x {
                *v = c.float("a node coordinate")?;
            }
            for _ in 0..extra {
                c.float("a parametric node coordinate")?;
            }
            if x.iter().any(|v| !v.is_finite()) {
                return c.fail(format!(
                    "node {} has a non-finite coordinate",
                    raw.node_tags[first + i]
                ));
            }
            raw.coords.push(x);
        }
        read += n as u64;
    }
    if read != total {
        return c.fail(format!(
            "the header says {total} nodes but the blocks hold {read}"
        ));
    }
    Ok(())
}

fn elements(c: &mut Cursor, raw: &mut Raw, dim: usize) -> Result<(), MeshError> {
    let s = c.size_t;
    let blocks = c.count("the number of element blocks", 12 + s, 4)?;
    let total = c.size("the number of elements")?;
    c.size("the minimum element tag")?;
    c.size("the maximum element tag")?;
    let mut read = 0u64;
    for _ in 0..blocks {
        let edim = c.int("an element block entity dimension")?;
        let etag = c.int("an element block entity tag")?;
        let etype = c.int("an element type")?;
        let Some((tname, tdim, nn)) = element_type(etype) else {
            return c.fail(format!(
                "element type {etype} (entity ({edim}, {etag})) is not a known Gmsh type; supported cells: {}",
                supported_cells(dim)
            ));
        };
        if edim != tdim as i32 {
            return c.fail(format!(
                "a block of {tname} elements (type {etype}) in an entity of dimension {edim}"
            ));
        }
        if tdim > dim {
            return c.fail(format!(
                "the file has {tdim}D elements ({tname} elements, type {etype}, entity {etag}) but is read as a {dim}D mesh"
            ));
        }
        if tdim == dim && !matches!((dim, etype), (2, 2) | (2, 3) | (3, 4) | (3, 5)) {
            return c.fail(format!(
                "{tname} elements (Gmsh type {etype}, entity {etag}) are not supported; {dim}D cells must be linear: {}",
                supported_cells(dim)
            ));
        }
        let n = c.count(
            &format!("the element count of the block of entity ({edim}, {etag})"),
            s * (1 + nn),
            1 + nn,
        )?;
        raw.dims_present[tdim] += n;
        if tdim == dim {
            raw.cells.reserve(n);
            raw.cell_nodes.reserve(n * nn);
            for _ in 0..n {
                let tag = c.size("an element tag")?;
                raw.cells.push((tag, etag, etype, raw.cell_nodes.len()));
                for _ in 0..nn {
                    let t = c.size("a node tag of an element")?;
                    raw.cell_nodes.push(t);
                }
            }
        } else {
            let list = raw.lower.entry((tdim, etag)).or_default();
            list.reserve(n);
            for _ in 0..n {
                let tag = c.size("an element tag")?;
                let mut nodes = Vec::with_capacity(nn);
                for _ in 0..nn {
                    nodes.push(c.size("a node tag of an element")?);
                }
                list.push((tag, nodes));
            }
        }
        read += n as u64;
    }
    if read != total {
        return c.fail(format!(
            "the header says {total} elements but the blocks hold {read}"
        ));
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Geometry and assembly

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

fn norm2(a: [f64; 3]) -> f64 {
    a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
}

fn max_edge2(p: &[[f64; 3]]) -> f64 {
    let mut m: f64 = 0.0;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            m = m.max(norm2(sub(p[i], p[j])));
        }
    }
    m
}

/// Area and centroid of a triangle or quadrangle in the xy plane. The
/// orientation does not matter; quadrangles must be convex.
fn polygon(p: &[[f64; 3]], tag: u64) -> Result<(f64, [f64; 3]), MeshError> {
    let o = p[0];
    let q: Vec<[f64; 2]> = p.iter().map(|v| [v[0] - o[0], v[1] - o[1]]).collect();
    let n = q.len();
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (a, b) = (q[i], q[(i + 1) % n]);
        let cr = a[0] * b[1] - b[0] * a[1];
        a2 += cr;
        cx += (a[0] + b[0]) * cr;
        cy += (a[1] + b[1]) * cr;
    }
    let l2 = max_edge2(p);
    let tol = 1e-12 * l2;
    let positive = a2.abs() / 2.0 > tol; // false for NaN too
    if !positive {
        return error(format!(
            "element {tag} has zero area (degenerate {}-node cell)",
            n
        ));
    }
    if n == 4 {
        for i in 0..4 {
            let (a, b, c) = (q[(i + 3) % 4], q[i], q[(i + 1) % 4]);
            let cr = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            if cr * a2.signum() < -tol {
                return error(format!(
                    "element {tag} is a non-convex or self-intersecting quadrangle"
                ));
            }
        }
    }
    let area = a2.abs() / 2.0;
    Ok((area, [o[0] + cx / (3.0 * a2), o[1] + cy / (3.0 * a2), 0.0]))
}

/// Volume and centroid of a tetrahedron or hexahedron (Gmsh node order); the
/// hexahedron is split into 24 tetrahedra (cell centre, face centre, edge),
/// which is exact for planar faces and gives the trilinear volume otherwise.
fn solid(p: &[[f64; 3]], tag: u64) -> Result<(f64, [f64; 3]), MeshError> {
    let o = p[0];
    let q: Vec<[f64; 3]> = p.iter().map(|v| sub(*v, o)).collect();
    let l2 = max_edge2(p);
    let tol = 1e-12 * l2 * l2.sqrt();
    let mut vol = 0.0;
    let mut c = [0.0; 3];
    let mut add = |a: [f64; 3], b: [f64; 3], cc: [f64; 3], d: [f64; 3]| -> bool {
        let v = det3(sub(b, a), sub(cc, a), sub(d, a)) / 6.0;
        vol += v;
        for k in 0..3 {
            c[k] += v * (a[k] + b[k] + cc[k] + d[k]) / 4.0;
        }
        v > tol
    };
    let ok = if q.len() == 4 {
        add(q[0], q[1], q[2], q[3])
    } else {
        const FACES: [[usize; 4]; 6] = [
            [0, 3, 2, 1],
            [4, 5, 6, 7],
            [0, 1, 5, 4],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [3, 0, 4, 7],
        ];
        let mean = |idx: &[usize]| {
            let mut m = [0.0; 3];
            for &i in idx {
                for k in 0..3 {
                    m[k] += q[i][k] / idx.len() as f64;
                }
            }
            m
        };
        let centre = mean(&[0, 1, 2, 3, 4, 5, 6, 7]);
        let mut all = true;
        for f in FACES {
            let fc = mean(&f);
            for i in 0..4 {
                // outward face (a, b) seen from outside, anticlockwise: tet (centre, a, b, fc) positive
                all &= add(centre, q[f[i]], q[f[(i + 1) % 4]], fc);
            }
        }
        all
    };
    let positive = vol > tol; // false for NaN too
    if !ok || !positive {
        let kind = if q.len() == 4 {
            "tetrahedron"
        } else {
            "hexahedron"
        };
        return error(format!(
            "element {tag} is a degenerate or inverted {kind} (volume {vol:e}; Gmsh orders nodes for a positive volume)"
        ));
    }
    Ok((
        vol,
        [o[0] + c[0] / vol, o[1] + c[1] / vol, o[2] + c[2] / vol],
    ))
}

enum TagIndex {
    Dense(Vec<usize>),
    Sparse(HashMap<u64, usize>),
}

impl TagIndex {
    fn get(&self, t: u64) -> Option<usize> {
        match self {
            TagIndex::Dense(v) => v.get(t as usize).copied().filter(|&i| i != usize::MAX),
            TagIndex::Sparse(m) => m.get(&t).copied(),
        }
    }
}

/// The node index of the tags read: dense when the largest tag is small
/// relative to the number of nodes, else a hash map; a tag seen twice is an error.
fn node_index(tags: &[u64]) -> Result<TagIndex, MeshError> {
    let n = tags.len();
    let max_tag = tags.iter().copied().max().unwrap_or(0);
    if max_tag <= 4 * n as u64 + 16 {
        let mut v = vec![usize::MAX; max_tag as usize + 1];
        for (i, &t) in tags.iter().enumerate() {
            if v[t as usize] != usize::MAX {
                return error(format!("$Nodes: node tag {t} appears twice"));
            }
            v[t as usize] = i;
        }
        Ok(TagIndex::Dense(v))
    } else {
        let mut m = HashMap::with_capacity(n);
        for (i, &t) in tags.iter().enumerate() {
            if m.insert(t, i).is_some() {
                return error(format!("$Nodes: node tag {t} appears twice"));
            }
        }
        Ok(TagIndex::Sparse(m))
    }
}

impl TagIndex {
    /// The index of node `t`, which element `what` refers to.
    fn lookup(&self, t: u64, what: &str) -> Result<usize, MeshError> {
        self.get(t).ok_or_else(|| MeshError {
            message: format!("$Elements: {what} refers to node {t}, which is not in $Nodes"),
        })
    }

    /// The indices of `tags`, the nodes element `what` refers to.
    fn lookup_all(&self, tags: &[u64], what: &str) -> Result<Vec<usize>, MeshError> {
        tags.iter().map(|&t| self.lookup(t, what)).collect()
    }
}

/// Refuses a 2D mesh with a node off the plane z = 0 (relative to its extent).
fn check_planar(coords: &[[f64; 3]], tags: &[u64]) -> Result<(), MeshError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in coords {
        for k in 0..2 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0);
    for (x, t) in coords.iter().zip(tags) {
        let planar = x[2].abs() <= 1e-10 * extent; // false for NaN too
        if !planar {
            return error(format!(
                "node {t} has z = {:e}: a 2D mesh must lie in the plane z = 0",
                x[2]
            ));
        }
    }
    Ok(())
}

/// The physical groups while the elements are read: named ones and those
/// the entities use, with the nodes each collects.
struct Groups {
    list: Vec<PhysicalGroup>,
    index: HashMap<(usize, i32), usize>,
    entities: HashMap<(usize, i32), Vec<i32>>,
    nodes: Vec<Vec<usize>>,
}

impl Groups {
    fn new(
        names: &BTreeMap<(usize, i32), String>,
        entities: HashMap<(usize, i32), Vec<i32>>,
    ) -> Self {
        let mut keys: BTreeMap<(usize, i32), String> = names.clone();
        for (&(d, _), phys) in &entities {
            for &p in phys {
                keys.entry((d, p)).or_default();
            }
        }
        let index: HashMap<(usize, i32), usize> =
            keys.keys().enumerate().map(|(i, &k)| (k, i)).collect();
        let list: Vec<PhysicalGroup> = keys
            .into_iter()
            .map(|((d, tag), name)| PhysicalGroup {
                dim: d,
                tag,
                name,
                nodes: vec![],
                cells: vec![],
                facets: vec![],
            })
            .collect();
        let nodes = vec![vec![]; list.len()];
        Groups {
            list,
            index,
            entities,
            nodes,
        }
    }

    /// The groups of entity `(d, etag)`, which element `what` belongs to.
    fn of(&self, d: usize, etag: i32, what: &str) -> Result<Vec<usize>, MeshError> {
        match self.entities.get(&(d, etag)) {
            Some(phys) => {
                let mut g: Vec<usize> = phys.iter().map(|&p| self.index[&(d, p)]).collect();
                g.sort_unstable();
                g.dedup();
                Ok(g)
            }
            None if !self.entities.is_empty() => error(format!(
                "$Elements: {what} belongs to entity ({d}, {etag}), which is not in $Entities"
            )),
            None => Ok(vec![]),
        }
    }

    /// The groups with their nodes, sorted.
    fn finish(mut self) -> Vec<PhysicalGroup> {
        for (g, mut nodes) in self.list.iter_mut().zip(self.nodes) {
            nodes.sort_unstable();
            nodes.dedup();
            g.nodes = nodes;
        }
        self.list
    }
}

fn build(raw: Raw, dim: usize) -> Result<Mesh, MeshError> {
    let index = node_index(&raw.node_tags)?;
    if dim == 2 {
        check_planar(&raw.coords, &raw.node_tags)?;
    }
    let mut groups = Groups::new(&raw.names, raw.entities.clone().unwrap_or_default());
    let cells = read_cells(&raw, dim, &index, &mut groups)?;
    read_lower(&raw, dim, &index, &mut groups)?;
    Ok(Mesh {
        nodes: raw.coords,
        node_tag: raw.node_tags,
        cells,
        groups: groups.finish(),
    })
}

/// The cells (elements of the mesh's dimension): nodes, centroid, measure, groups.
fn read_cells(
    raw: &Raw,
    dim: usize,
    index: &TagIndex,
    groups: &mut Groups,
) -> Result<MeshCells, MeshError> {
    let mut cells = MeshCells {
        dim,
        ..Default::default()
    };
    let count = raw.cells.len();
    if count == 0 {
        let found: Vec<String> = (0..4)
            .filter(|&d| raw.dims_present[d] > 0)
            .map(|d| format!("{d}D"))
            .collect();
        return error(format!(
            "the file has no {dim}D elements (found: {}); with physical groups defined, Gmsh saves only the \
             elements of physical groups (add a {dim}D physical group or set Mesh.SaveAll = 1)",
            if found.is_empty() { "none".to_string() } else { found.join(", ") }
        ));
    }
    cells.element_tag.reserve(count);
    cells.centroid.reserve(count);
    cells.measure.reserve(count);
    cells.nodes.reserve(count);
    cells.groups.reserve(count);
    let mut entity_groups: HashMap<i32, Vec<usize>> = HashMap::new();
    for (ci, &(tag, etag, etype, off)) in raw.cells.iter().enumerate() {
        let nn = element_type(etype).map_or(0, |t| t.2);
        let what = format!("element {tag}");
        let idx = index.lookup_all(&raw.cell_nodes[off..off + nn], &what)?;
        let mut sorted = idx.clone();
        sorted.sort_unstable();
        if sorted.windows(2).any(|w| w[0] == w[1]) {
            return error(format!("$Elements: element {tag} repeats a node"));
        }
        let p: Vec<[f64; 3]> = idx.iter().map(|&i| raw.coords[i]).collect();
        let (m, c) = if dim == 2 {
            polygon(&p, tag)?
        } else {
            solid(&p, tag)?
        };
        let g = match entity_groups.get(&etag) {
            Some(g) => g.clone(),
            None => {
                let g = groups.of(dim, etag, &what)?;
                entity_groups.insert(etag, g.clone());
                g
            }
        };
        for &gi in &g {
            groups.list[gi].cells.push(ci);
            groups.nodes[gi].extend_from_slice(&idx);
        }
        cells.element_tag.push(tag);
        cells.centroid.push(c);
        cells.measure.push(m);
        cells.nodes.push(idx);
        cells.groups.push(g);
    }
    Ok(cells)
}

/// The lower-dimensional elements: their nodes join their groups, and those
/// of dimension `dim − 1` are the groups' facets.
fn read_lower(
    raw: &Raw,
    dim: usize,
    index: &TagIndex,
    groups: &mut Groups,
) -> Result<(), MeshError> {
    let mut lower: Vec<_> = raw.lower.iter().collect();
    lower.sort_by_key(|(k, _)| **k);
    for (&(d, etag), elements) in lower {
        let Some((first, _)) = elements.first() else {
            continue;
        };
        let g = groups.of(d, etag, &format!("element {first}"))?;
        for (tag, tags) in elements {
            let idx = index.lookup_all(tags, &format!("element {tag}"))?;
            for &gi in &g {
                groups.nodes[gi].extend_from_slice(&idx);
                if d + 1 == dim {
                    groups.list[gi].facets.push(idx.clone());
                }
            }
        }
    }
    Ok(())
}
