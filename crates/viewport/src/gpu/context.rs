//! A wgpu device without a window, for offscreen rendering, GPU deformation and tests.

use thiserror::Error;

/// Why no GPU device could be had.
#[derive(Debug, Error)]
pub enum GpuError {
    /// No adapter at all (no GPU driver, no software Vulkan).
    #[error(
        "no graphics adapter found: install a GPU driver or a software Vulkan driver \
         (on Debian: apt-get install mesa-vulkan-drivers) ({0})"
    )]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("the graphics adapter refused a device: {0}")]
    Device(String),
    /// Reading rendered pixels back failed.
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
}

/// A device and its queue, with what the adapter is.
#[derive(Debug, Clone)]
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend and type.
    pub adapter_info: wgpu::AdapterInfo,
    /// Whether compute shaders are available (GPU deformation); the CPU path is used otherwise.
    pub compute: bool,
    /// Whether 4× MSAA works for the colour format used offscreen.
    pub msaa4: bool,
}

/// The colour format of offscreen images: colours are written as authored (no sRGB encoding),
/// as in egui's usual non-sRGB surfaces.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl GpuContext {
    /// A headless device on the best adapter (backends from `WGPU_BACKEND` when set).
    pub fn headless() -> Result<Self, GpuError> {
        pollster::block_on(Self::headless_async())
    }

    async fn headless_async() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        Self::from_adapter(&adapter).await
    }

    /// A device on `adapter`, asking for its own limits (large meshes need large buffers).
    pub async fn from_adapter(adapter: &wgpu::Adapter) -> Result<Self, GpuError> {
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("starcages"),
                required_features: wgpu::Features::empty(),
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Self::from_device(adapter, device, queue))
    }

    /// Wraps an existing device (the editor's, from eframe).
    pub fn from_device(adapter: &wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Self {
        let compute = adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS);
        let msaa4 = adapter
            .get_texture_format_features(OFFSCREEN_FORMAT)
            .flags
            .sample_count_supported(4);
        Self {
            device,
            queue,
            adapter_info: adapter.get_info(),
            compute,
            msaa4,
        }
    }

    /// Waits until the GPU finished the submitted work.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }
}
