//! GPU device creation, and waiting for a buffer to be read back.
//!
//! Kept apart from the renderer (which takes `&Device, &Queue`) so that tests
//! and callers can bring their own device. There is no GPU on the development
//! and CI machines: Vulkan (Mesa lavapipe) is tried first, then GL (llvmpipe
//! through EGL); both give exact colours. `UFCSR_BACKEND=vulkan|gl` or the
//! `--backend` option forces one.

use crate::error::{CaptureError, Result};

/// Maps `slice` for reading and waits until it is mapped (the one way every
/// readback in this crate waits on the GPU). `what` names the data in errors.
pub(crate) fn map_for_reading(
    device: &wgpu::Device,
    slice: &wgpu::BufferSlice<'_>,
    what: &str,
) -> Result<()> {
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        let _ = sender.send(result);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| CaptureError::Gpu(e.to_string()))?;
    receiver
        .recv()
        .map_err(|_| CaptureError::Gpu(format!("{what} was never mapped")))?
        .map_err(|e| CaptureError::Gpu(format!("{what} readback failed: {e}")))
}

/// A created device with a description of its adapter.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: wgpu::AdapterInfo,
}

/// Which backend to try.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// Vulkan, then GL.
    #[default]
    Auto,
    Vulkan,
    Gl,
}

// Parsing text is for the `UFCSR_BACKEND` variable (the command line has its own choice).

impl std::str::FromStr for Backend {
    type Err = CaptureError;

    fn from_str(text: &str) -> Result<Backend> {
        match text.to_ascii_lowercase().as_str() {
            "auto" | "" => Ok(Backend::Auto),
            "vulkan" | "vk" => Ok(Backend::Vulkan),
            "gl" | "gles" | "opengl" => Ok(Backend::Gl),
            other => {
                Err(CaptureError::BadOptions(format!("backend must be auto, vulkan or gl, not {other:?}")))
            }
        }
    }
}

impl Gpu {
    /// Creates a device, honouring `UFCSR_BACKEND` when `backend` is `Auto`.
    pub fn create(backend: Backend) -> Result<Gpu> {
        let backend = match (backend, std::env::var("UFCSR_BACKEND")) {
            (Backend::Auto, Ok(text)) => text.parse()?,
            (backend, _) => backend,
        };
        let order: &[wgpu::Backends] = match backend {
            Backend::Auto => &[wgpu::Backends::VULKAN, wgpu::Backends::GL],
            Backend::Vulkan => &[wgpu::Backends::VULKAN],
            Backend::Gl => &[wgpu::Backends::GL],
        };
        let mut failures = Vec::new();
        for &backends in order {
            match pollster::block_on(create_with(backends)) {
                Ok(gpu) => return Ok(gpu),
                Err(error) => failures.push(format!("{backends:?}: {error}")),
            }
        }
        Err(CaptureError::Gpu(format!(
            "no usable adapter ({}). Without a GPU install Mesa's software drivers: \
             apt-get install -y mesa-vulkan-drivers libvulkan1",
            failures.join("; ")
        )))
    }

    /// One line naming the adapter and backend.
    pub fn describe(&self) -> String {
        format!("{} ({:?}, {:?})", self.adapter.name, self.adapter.backend, self.adapter.device_type)
    }
}

async fn create_with(backends: wgpu::Backends) -> Result<Gpu> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        })
        .await
        .map_err(|e| CaptureError::Gpu(e.to_string()))?;
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("ufcsr-capture"),
            // Whatever the adapter offers: texture sizes up to the palette's
            // 4096 are needed, nothing exotic.
            required_limits: adapter.limits(),
            // f64 in shaders where the adapter has it: the exact measure
            // (`unobstructed_gpu`) needs it; rendering does not.
            required_features: adapter.features() & wgpu::Features::SHADER_F64,
            ..Default::default()
        })
        .await
        .map_err(|e| CaptureError::Gpu(e.to_string()))?;
    Ok(Gpu { device, queue, adapter: adapter.get_info() })
}
