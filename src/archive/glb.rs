//! Binary glTF building blocks shared by `vehicle.glb`, `heatmap.glb` and
//! `scene.glb`, and the one axis rule they all follow.
//!
//! ufcsr's frames (the vehicle's: x forward, y left, z up; the world's: x
//! east, y north, z up) are z up; glTF is +Y up with an asset's front facing
//! +Z and its left along +X. Every file ufcsr writes stores positions in
//! glTF's axes: frame `(x, y, z)` is glTF `(y, z, x)`, a cyclic permutation
//! and so a proper rotation (no mirroring, exact in floating point). The
//! positions are converted rather than hung under a rotated root node so
//! that the accessors hold what every viewer and importer shows, and a
//! Blender or Unity user sees no extra rotated parent. Files written so are
//! marked in `asset.extras` ([`AXES_MARK`]); a ufcsr file without the mark
//! is from before the rule and holds z-up frame coordinates
//! ([`FileAxes::of`]).

use std::borrow::Cow;

use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;

/// The key in `asset.extras` that marks a file written in glTF's axes.
pub(crate) const AXES_MARK: &str = "ufcsr_axes";

/// The mark's value, saying what the axes are (for people reading the JSON).
pub(crate) const AXES_NOTE: &str = "glTF: +Y up, front +Z; ufcsr frame (x, y, z) is glTF (y, z, x)";

/// Whether an accessor records its values' bounds (`min`/`max`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Bounds {
    /// Recorded: glTF requires them for positions.
    Written,
    /// Left out (UVs and other attributes).
    Omitted,
}

/// A ufcsr frame point (z up) in glTF's axes.
pub(crate) fn to_gltf_axes([x, y, z]: [f32; 3]) -> [f32; 3] {
    [y, z, x]
}

/// A glTF point in the ufcsr frame (z up): the inverse of [`to_gltf_axes`].
pub(crate) fn from_gltf_axes([x, y, z]: [f32; 3]) -> [f32; 3] {
    [z, x, y]
}

/// How a file's positions are to be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FileAxes {
    /// glTF's axes: ufcsr's files with the mark, and every other program's.
    Gltf,
    /// The ufcsr frame as is (z up): a ufcsr file from before the rule.
    OldUfcsrFrame,
}

impl FileAxes {
    /// The rule: the mark means glTF axes; a generator `ufcsr <version>`
    /// without it means an old z-up file; anything else follows glTF.
    pub(crate) fn of(document: &gltf::Document) -> FileAxes {
        let asset = &document.as_json().asset;
        let marked = asset
            .extras
            .as_ref()
            .and_then(|raw| serde_json::from_str::<serde_json::Value>(raw.get()).ok())
            .is_some_and(|extras| extras.get(AXES_MARK).is_some());
        let old_ufcsr = asset
            .generator
            .as_deref()
            .and_then(|g| g.strip_prefix("ufcsr "))
            .is_some_and(|version| version.starts_with(|c: char| c.is_ascii_digit()));
        if old_ufcsr && !marked { FileAxes::OldUfcsrFrame } else { FileAxes::Gltf }
    }

    /// A file point (after node transforms) in the ufcsr frame.
    pub(crate) fn to_frame(self, p: [f32; 3]) -> [f32; 3] {
        match self {
            FileAxes::Gltf => from_gltf_axes(p),
            FileAxes::OldUfcsrFrame => p,
        }
    }
}

/// A glTF document being built with its one binary buffer.
pub(crate) struct GlbBuilder {
    pub root: json::Root,
    bin: Vec<u8>,
    buffer: json::Index<json::Buffer>,
}

impl GlbBuilder {
    /// An empty document, marked as written in glTF's axes.
    pub(crate) fn new() -> GlbBuilder {
        let mut root = json::Root::default();
        let buffer = root.push(json::Buffer {
            byte_length: USize64(0), // set by `finish`, once the data is all in
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: None,
        });
        root.asset.generator = Some(concat!("ufcsr ", env!("CARGO_PKG_VERSION")).into());
        let mark = serde_json::json!({ AXES_MARK: AXES_NOTE }).to_string();
        root.asset.extras = serde_json::value::RawValue::from_string(mark).ok();
        GlbBuilder { root, bin: Vec::new(), buffer }
    }

    /// Appends `bytes` (4-byte aligned) as a buffer view; vertex data has a stride.
    pub(crate) fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> json::Index<json::buffer::View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: self.buffer,
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: stride.map(json::buffer::Stride),
            name: None,
            target: stride.map(|_| Valid(json::buffer::Target::ArrayBuffer)),
            extensions: None,
            extras: Default::default(),
        })
    }

    /// A float vertex attribute (`N` = 2 or 3 components); positions get their bounds
    /// (glTF requires them there).
    pub(crate) fn attribute<const N: usize>(
        &mut self,
        values: &[[f32; N]],
        bounds_record: Bounds,
    ) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(4 * N));
        let kind = if N == 2 { json::accessor::Type::Vec2 } else { json::accessor::Type::Vec3 };
        let (min, max) = if bounds_record == Bounds::Written {
            let (min, max) = bounds(values);
            (Some(json::Value::from(min.to_vec())), Some(json::Value::from(max.to_vec())))
        } else {
            (None, None)
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: Some(USize64(0)),
            count: USize64::from(values.len()),
            component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::F32)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(kind),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// An embedded PNG as a nearest-filtered texture: a texel is one point
    /// of the vehicle (or one palette colour), never a blend.
    pub(crate) fn png_texture(&mut self, png: &[u8], name: &str) -> json::Index<json::Texture> {
        let view = self.view(png, None);
        let image = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: Some(name.into()),
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        let sampler = self.root.push(json::texture::Sampler {
            mag_filter: Some(Valid(json::texture::MagFilter::Nearest)),
            min_filter: Some(Valid(json::texture::MinFilter::Nearest)),
            name: None,
            wrap_s: Valid(json::texture::WrappingMode::ClampToEdge),
            wrap_t: Valid(json::texture::WrappingMode::ClampToEdge),
            extensions: None,
            extras: Default::default(),
        });
        self.root.push(json::Texture {
            name: Some(name.into()),
            sampler: Some(sampler),
            source: image,
            extensions: None,
            extras: Default::default(),
        })
    }

    /// An unlit, double-sided material: the colours are the texture's (or
    /// `color`, linear RGBA), never the viewer's lighting.
    pub(crate) fn unlit_material(
        &mut self,
        name: &str,
        texture: Option<json::Index<json::Texture>>,
        color: [f32; 4],
    ) -> json::Index<json::Material> {
        if !self.root.extensions_used.iter().any(|e| e == "KHR_materials_unlit") {
            self.root.extensions_used.push("KHR_materials_unlit".into());
        }
        let base_color_texture = texture.map(|index| json::texture::Info {
            index,
            tex_coord: 0,
            extensions: None,
            extras: Default::default(),
        });
        self.root.push(json::Material {
            name: Some(name.into()),
            double_sided: true,
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_texture,
                base_color_factor: json::material::PbrBaseColorFactor(color),
                metallic_factor: json::material::StrengthFactor(0.0),
                roughness_factor: json::material::StrengthFactor(1.0),
                ..Default::default()
            },
            // Other material extensions exist when other crates enable
            // their gltf-json features, hence the struct update.
            #[allow(clippy::needless_update)]
            extensions: Some(json::extensions::material::Material {
                unlit: Some(json::extensions::material::Unlit {}),
                ..Default::default()
            }),
            ..Default::default()
        })
    }

    /// A node with a one-primitive triangle-list mesh, both named `name`.
    pub(crate) fn mesh_node(
        &mut self,
        name: &str,
        attributes: Vec<(json::mesh::Semantic, json::Index<json::Accessor>)>,
        material: json::Index<json::Material>,
        translation: Option<[f32; 3]>,
    ) -> json::Index<json::Node> {
        let primitive = json::mesh::Primitive {
            attributes: attributes.into_iter().map(|(semantic, index)| (Valid(semantic), index)).collect(),
            extensions: None,
            extras: Default::default(),
            indices: None,
            material: Some(material),
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        };
        let mesh = self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name.into()),
            primitives: vec![primitive],
            weights: None,
        });
        self.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(name.into()),
            translation,
            ..Default::default()
        })
    }

    /// The GLB bytes of a document whose scene holds `nodes`.
    pub(crate) fn finish(mut self, nodes: Vec<json::Index<json::Node>>) -> Result<Vec<u8>, String> {
        self.root.buffers[0].byte_length = USize64::from(self.bin.len());
        let scene =
            self.root.push(json::Scene { extensions: None, extras: Default::default(), name: None, nodes });
        self.root.scene = Some(scene);
        let json = json::serialize::to_vec(&self.root).map_err(|e| format!("glTF JSON: {e}"))?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
            json: Cow::Owned(json),
            bin: Some(Cow::Owned(self.bin)),
        };
        glb.to_vec().map_err(|e| format!("GLB: {e}"))
    }
}

fn bounds<const N: usize>(values: &[[f32; N]]) -> ([f32; N], [f32; N]) {
    let mut min = [f32::MAX; N];
    let mut max = [f32::MIN; N];
    for p in values {
        for axis in 0..N {
            min[axis] = min[axis].min(p[axis]);
            max[axis] = max[axis].max(p[axis]);
        }
    }
    (min, max)
}

/// The 4×4 column-major product `a · b` (glTF node matrices).
pub(crate) fn multiply(a: &[[f32; 4]; 4], b: &[[f32; 4]; 4]) -> [[f32; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for (column, b_column) in out.iter_mut().zip(b) {
        for (row, value) in column.iter_mut().enumerate() {
            *value = (0..4).map(|k| a[k][row] * b_column[k]).sum();
        }
    }
    out
}

/// A point through a column-major affine matrix.
pub(crate) fn transform_point(m: &[[f32; 4]; 4], [x, y, z]: [f32; 3]) -> [f32; 3] {
    [0, 1, 2].map(|row| m[0][row] * x + m[1][row] * y + m[2][row] * z + m[3][row])
}

/// The identity matrix.
pub(crate) const IDENTITY: [[f32; 4]; 4] =
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_axis_map_is_a_proper_rotation_and_its_own_inverse_undoes_it() {
        // Images of the frame's unit axes: forward -> +Z, left -> +X, up -> +Y.
        assert_eq!(to_gltf_axes([1.0, 0.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(to_gltf_axes([0.0, 1.0, 0.0]), [1.0, 0.0, 0.0]);
        assert_eq!(to_gltf_axes([0.0, 0.0, 1.0]), [0.0, 1.0, 0.0]);
        // Columns (+Z, +X, +Y): determinant +1 (a cyclic permutation).
        let m = [[0.0f32, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        assert_eq!(det, 1.0);
        assert_eq!(from_gltf_axes(to_gltf_axes([1.5, -2.0, 3.25])), [1.5, -2.0, 3.25]);
    }

    #[test]
    fn node_matrices_compose_translation_after_scale() {
        let mut scale = IDENTITY;
        scale[0][0] = 2.0;
        let mut shift = IDENTITY;
        shift[3] = [1.0, 2.0, 3.0, 1.0];
        assert_eq!(transform_point(&multiply(&shift, &scale), [1.0, 1.0, 1.0]), [3.0, 3.0, 4.0]);
    }
}
