//! Where a tile is drawn and how its pixels come back: the colour and depth
//! targets and the readback buffer, and the two steps after the render pass
//! (copy into the buffer with rows padded to 256 bytes, then map it and strip
//! the padding).

use crate::error::{CaptureError, Result};

/// A rectangle of pixels in a tile (x to the right, y down), non-empty.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PixelRect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl PixelRect {
    /// The whole of a `size` tile.
    pub fn whole(size: [u32; 2]) -> PixelRect {
        PixelRect { x: 0, y: 0, width: size[0], height: size[1] }
    }

    /// Pixels covered.
    pub fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }
}

/// The colour and depth targets of one tile, and its readback buffer.
pub(crate) struct TileTarget {
    color: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    pub depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    size: [u32; 2],
    /// Bytes per readback row: a whole tile row padded to
    /// `COPY_BYTES_PER_ROW_ALIGNMENT` (256), as wgpu requires.
    padded_row: u32,
}

impl TileTarget {
    /// Targets and a readback buffer for `size` tiles.
    pub(crate) fn new(device: &wgpu::Device, size: [u32; 2]) -> TileTarget {
        let [width, height] = size;
        let texture = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = texture(
            "tile colour",
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth =
            texture("tile depth", wgpu::TextureFormat::Depth32Float, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let padded_row = padded_row_bytes(width);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        TileTarget {
            color_view: color.create_view(&Default::default()),
            color,
            depth_view: depth.create_view(&Default::default()),
            readback,
            size,
            padded_row,
        }
    }

    /// Tile size in pixels.
    pub(crate) fn size(&self) -> [u32; 2] {
        self.size
    }

    /// Records the copy of `region` of the colour target into the readback
    /// buffer, rows `padded_row` bytes apart from offset 0.
    pub(crate) fn copy_to_readback(&self, encoder: &mut wgpu::CommandEncoder, region: PixelRect) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.color,
                mip_level: 0,
                origin: wgpu::Origin3d { x: region.x, y: region.y, z: 0 },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(region.height),
                },
            },
            wgpu::Extent3d { width: region.width, height: region.height, depth_or_array_layers: 1 },
        );
    }

    /// Waits for the submitted copy of `region`, maps the buffer and returns
    /// the region's pixels, RGBA8, tightly packed rows top to bottom.
    pub(crate) fn read_back(&self, device: &wgpu::Device, region: PixelRect) -> Result<Vec<u8>> {
        let used = u64::from(self.padded_row) * u64::from(region.height);
        let slice = self.readback.slice(..used);
        crate::render::gpu::map_for_reading(device, &slice, "tile")?;
        let row = (region.width * 4) as usize;
        let mut pixels = Vec::with_capacity(row * region.height as usize);
        {
            let mapped =
                slice.get_mapped_range().map_err(|e| CaptureError::Gpu(format!("readback mapping: {e}")))?;
            for y in 0..region.height as usize {
                let start = y * self.padded_row as usize;
                pixels.extend_from_slice(&mapped[start..start + row]);
            }
        }
        self.readback.unmap();
        Ok(pixels)
    }
}

/// `width` RGBA8 pixels rounded up to wgpu's 256-byte row alignment.
fn padded_row_bytes(width: u32) -> u32 {
    (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_padded_to_256_bytes() {
        assert_eq!(padded_row_bytes(64), 256);
        assert_eq!(padded_row_bytes(65), 512);
        assert_eq!(padded_row_bytes(1284), 5376);
        assert_eq!(PixelRect::whole([10, 20]).pixels(), 200);
    }
}
