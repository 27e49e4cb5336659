//! A 3D finding's scene as a glTF 2.0 binary (`.glb`), for any glTF viewer (Blender, three.js,
//! the Windows 3D viewer, online viewers).
//!
//! The document (built with `gltf-json`) has one scene whose root node turns the machine frame
//! into glTF's: millimetres to metres (× 0.001), machine `z` to glTF +X, machine `x` to glTF +Y
//! (up), machine `y` to glTF +Z, a proper rotation, so a viewer's default camera looks at the
//! lathe's own view (z to the right, x up). Under it, one node per part, named after the
//! component, posed by a node matrix (its isometry); its mesh holds the part's vertices in its own
//! frame (positions as `f32`, indices as `u32`) and a material per role, coloured as in the SVG
//! views (the stock half transparent). Parts that share one mesh and one role share one glTF
//! mesh. The first contact is a small red octahedron named "first contact".
//!
//! Bad triangles (an index past the vertices, a vertex that is not finite or past
//! `scene3::MAX_COORD`) are left out; a part left with none, or with a pose whose translation is
//! not drawable, is a node without a mesh. The
//! container is written here: a 12-byte header, a JSON chunk padded with spaces and a BIN chunk
//! padded with zeros, each to 4 bytes.

use super::scene3::{Part3, Role3, Snapshot3};
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use nalgebra::Point3;
use std::collections::HashMap;
use std::sync::Arc;

const MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// The machine frame in glTF's: columns are the images of machine x, y, z (and the origin), in
/// metres.
const ROOT_MATRIX: [f32; 16] = [
    0.0, 0.001, 0.0, 0.0, // machine x → glTF +Y
    0.0, 0.0, 0.001, 0.0, // machine y → glTF +Z
    0.001, 0.0, 0.0, 0.0, // machine z → glTF +X
    0.0, 0.0, 0.0, 1.0,
];

/// The name of the root node (the machine frame).
pub const ROOT_NAME: &str = "machine frame (mm)";
/// The name of the contact marker's node.
pub const CONTACT_NAME: &str = "first contact";

/// The glTF binary of a snapshot.
pub fn glb(s: &Snapshot3) -> Vec<u8> {
    let mut b = Builder::default();
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("latheguard {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    let mut materials: HashMap<Role3, json::Index<json::Material>> = HashMap::new();
    let mut meshes: HashMap<(usize, Role3), Option<json::Index<json::Mesh>>> = HashMap::new();
    let mut children = Vec::new();
    for part in &s.parts {
        let matrix = pose_matrix(part);
        let key = (Arc::as_ptr(&part.mesh) as usize, part.role);
        let mesh = match meshes.get(&key) {
            Some(m) => *m,
            None => {
                let material = *materials
                    .entry(part.role)
                    .or_insert_with(|| root.push(material(part.role)));
                let m = b.mesh(&mut root, part, material);
                meshes.insert(key, m);
                m
            }
        };
        children.push(root.push(json::Node {
            name: Some(part.name.clone()),
            matrix,
            mesh: matrix.and(mesh),
            ..Default::default()
        }));
    }
    if let Some(c) = s.contact() {
        let size = (0.015 * s.bounds().size()).clamp(0.5, 25.0);
        let material = root.push(contact_material());
        let mesh = b.marker(&mut root, size, material);
        children.push(root.push(json::Node {
            name: Some(CONTACT_NAME.to_string()),
            translation: Some([c.x as f32, c.y as f32, c.z as f32]),
            mesh: Some(mesh),
            ..Default::default()
        }));
    }
    let top = root.push(json::Node {
        name: Some(ROOT_NAME.to_string()),
        matrix: Some(ROOT_MATRIX),
        children: (!children.is_empty()).then_some(children),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(format!("line {}: {}", s.line, s.title)),
        nodes: vec![top],
    });
    root.scene = Some(scene);
    if !b.bin.is_empty() {
        let buffer = root.push(json::Buffer {
            byte_length: USize64::from(b.bin.len()),
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: None,
        });
        for v in &mut root.buffer_views {
            v.buffer = buffer;
        }
    }
    let text = json::serialize::to_vec(&root).unwrap_or_default();
    container(&text, &b.bin)
}

/// One glTF binary of a batch: which file and finding of the report it shows, its file name,
/// its bytes.
pub struct GlbFile {
    pub file: usize,
    pub finding: usize,
    pub name: String,
    pub bytes: Vec<u8>,
}

/// A `.glb` for every finding of a batch that carries a 3D snapshot, in report order; named as
/// the SVG pictures are (`programs__mill.nc.L12.collision.T05-drill.sub-chuck.glb`), unique
/// within the batch. Findings of the 2D path have none.
pub fn files(r: &super::Report) -> Vec<GlbFile> {
    let mut out = Vec::new();
    let mut used = std::collections::HashSet::new();
    for (fi, f) in r.files.iter().enumerate() {
        for (xi, x) in f.findings.iter().enumerate() {
            let Some(s) = x.snapshot3.as_deref() else { continue };
            let base = super::svg::name(&f.path, x);
            let mut name = format!("{base}.glb");
            let mut k = 2;
            while !used.insert(name.clone()) {
                name = format!("{base}.{k}.glb");
                k += 1;
            }
            out.push(GlbFile {
                file: fi,
                finding: xi,
                name,
                bytes: glb(s),
            });
        }
    }
    out
}

/// The 12-byte header and the two chunks.
fn container(json_text: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let json_len = json_text.len() + pad(json_text.len());
    let bin_len = bin.len() + pad(bin.len());
    let total = 12 + 8 + json_len + if bin.is_empty() { 0 } else { 8 + bin_len };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(json_text);
    out.resize(out.len() + pad(json_text.len()), b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(bin);
        out.resize(out.len() + pad(bin.len()), 0);
    }
    out
}

/// A part's pose as a column-major node matrix; `None` when it is not finite or its translation
/// is past `scene3::MAX_COORD`.
fn pose_matrix(p: &Part3) -> Option<[f32; 16]> {
    if !super::scene3::drawable(&Point3::from(p.pose.translation.vector)) {
        return None;
    }
    let h = p.pose.to_homogeneous();
    let mut m = [0f32; 16];
    for (o, v) in m.iter_mut().zip(h.as_slice()) {
        if !v.is_finite() {
            return None;
        }
        *o = *v as f32;
    }
    Some(m)
}

/// An sRGB `#rrggbb` colour as glTF's linear base colour factor.
fn linear(hex: &str, alpha: f32) -> [f32; 4] {
    let c = |i: usize| {
        let v = u8::from_str_radix(hex.get(i..i + 2).unwrap_or("80"), 16).unwrap_or(128) as f32 / 255.0;
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    [c(1), c(3), c(5), alpha]
}

fn material(role: Role3) -> json::Material {
    let (fill, _) = role.colours();
    let stock = role == Role3::Stock;
    json::Material {
        name: Some(role.name().to_string()),
        alpha_mode: Valid(if stock {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        // Meshes may be wound either way: never cull a face.
        double_sided: true,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(linear(fill, if stock { 0.55 } else { 1.0 })),
            metallic_factor: json::material::StrengthFactor(0.1),
            roughness_factor: json::material::StrengthFactor(0.7),
            ..Default::default()
        },
        ..Default::default()
    }
}

fn contact_material() -> json::Material {
    let red = linear(super::svg::OVERLAP, 1.0);
    json::Material {
        name: Some(CONTACT_NAME.to_string()),
        double_sided: true,
        emissive_factor: json::material::EmissiveFactor([red[0], red[1], red[2]]),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(red),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.5),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The binary buffer as it fills, with its views' offsets (every view 4-byte aligned: all its
/// components are 4 bytes).
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
}

impl Builder {
    fn view(
        &mut self,
        root: &mut json::Root,
        bytes: &[u8],
        target: json::buffer::Target,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        root.push(json::buffer::View {
            // Set to the one buffer once it exists.
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: Some(Valid(target)),
        })
    }

    /// A triangle mesh from positions and indices; `None` when there is no triangle.
    fn triangles(
        &mut self,
        root: &mut json::Root,
        name: &str,
        positions: &[[f32; 3]],
        indices: &[u32],
        material: json::Index<json::Material>,
    ) -> Option<json::Index<json::Mesh>> {
        if indices.is_empty() || positions.is_empty() {
            return None;
        }
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        let mut bytes = Vec::with_capacity(positions.len() * 12);
        for p in positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
                bytes.extend_from_slice(&p[k].to_le_bytes());
            }
        }
        let pv = self.view(root, &bytes, json::buffer::Target::ArrayBuffer);
        let pos = root.push(json::Accessor {
            buffer_view: Some(pv),
            byte_offset: Some(USize64(0)),
            count: USize64::from(positions.len()),
            component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::F32)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(json::accessor::Type::Vec3),
            min: Some(json::Value::from(lo.to_vec())),
            max: Some(json::Value::from(hi.to_vec())),
            name: None,
            normalized: false,
            sparse: None,
        });
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let iv = self.view(root, &bytes, json::buffer::Target::ElementArrayBuffer);
        let idx = root.push(json::Accessor {
            buffer_view: Some(iv),
            byte_offset: Some(USize64(0)),
            count: USize64::from(indices.len()),
            component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::U32)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        });
        let mut attributes = std::collections::BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), pos);
        Some(root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name.to_string()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(idx),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        }))
    }

    /// A part's mesh in its own frame: only the good triangles, only the vertices they use.
    fn mesh(
        &mut self,
        root: &mut json::Root,
        part: &Part3,
        material: json::Index<json::Material>,
    ) -> Option<json::Index<json::Mesh>> {
        let vs = &part.mesh.vertices;
        let ok = |i: u32| vs.get(i as usize).is_some_and(super::scene3::drawable);
        let mut map: HashMap<u32, u32> = HashMap::new();
        let mut positions: Vec<[f32; 3]> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        for t in &part.mesh.triangles {
            if !t.iter().all(|&i| ok(i)) {
                continue;
            }
            for &i in t {
                let next = positions.len() as u32;
                let k = *map.entry(i).or_insert_with(|| {
                    let p = vs[i as usize];
                    positions.push([p.x as f32, p.y as f32, p.z as f32]);
                    next
                });
                indices.push(k);
            }
        }
        self.triangles(root, &part.name, &positions, &indices, material)
    }

    /// An octahedron of half-diagonal `r` about the origin.
    fn marker(
        &mut self,
        root: &mut json::Root,
        r: f64,
        material: json::Index<json::Material>,
    ) -> json::Index<json::Mesh> {
        let r = r as f32;
        let positions = [
            [r, 0.0, 0.0],
            [-r, 0.0, 0.0],
            [0.0, r, 0.0],
            [0.0, -r, 0.0],
            [0.0, 0.0, r],
            [0.0, 0.0, -r],
        ];
        let indices = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
        self.triangles(root, CONTACT_NAME, &positions, &indices, material)
            .unwrap_or_else(|| json::Index::new(0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_container_pads_json_with_spaces_and_bin_with_zeros() {
        let out = container(b"{}", &[1, 2, 3, 4, 5]);
        assert_eq!(&out[0..4], b"glTF");
        assert_eq!(u32::from_le_bytes(out[8..12].try_into().unwrap()) as usize, out.len());
        assert_eq!(u32::from_le_bytes(out[12..16].try_into().unwrap()), 4);
        assert_eq!(&out[20..24], b"{}  ");
        assert_eq!(u32::from_le_bytes(out[24..28].try_into().unwrap()), 8);
        assert_eq!(&out[28..32], b"BIN\0");
        assert_eq!(&out[32..40], &[1, 2, 3, 4, 5, 0, 0, 0]);
        assert_eq!(out.len() % 4, 0);
    }

    #[test]
    fn the_root_matrix_is_a_proper_rotation_in_metres() {
        let m = nalgebra::Matrix4::from_column_slice(&ROOT_MATRIX.map(|v| v as f64 * 1000.0));
        let r = m.fixed_view::<3, 3>(0, 0).map(f64::round);
        assert_eq!(r.determinant(), 1.0);
        assert_eq!(r * r.transpose(), nalgebra::Matrix3::identity());
        // Machine x is glTF's up, machine z glTF's +X (the lathe's view from the default camera).
        assert_eq!(r * nalgebra::Vector3::x(), nalgebra::Vector3::y());
        assert_eq!(r * nalgebra::Vector3::z(), nalgebra::Vector3::x());
    }
}
