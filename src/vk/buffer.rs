//! Buffers placed in our allocator.

use super::gpu::Gpu;
use super::memory::{Allocation, Location, ResourceKind};
use super::owned::Owned;
use crate::error::{Error, Result, VkContext};
use ash::vk;

/// Plain data that any byte pattern of its size is a valid value of (what a readback can hold).
pub trait Pod: Copy + Default + 'static {}
impl Pod for u8 {}
impl Pod for u16 {}
impl Pod for u32 {}
impl Pod for f32 {}

/// A buffer and its memory, both released when dropped.
pub struct Buffer<'g> {
    gpu: &'g Gpu,
    pub raw: vk::Buffer,
    pub size: u64,
    allocation: Option<Allocation>,
}

impl<'g> Buffer<'g> {
    pub fn new(gpu: &'g Gpu, name: &str, size: u64, usage: vk::BufferUsageFlags, location: Location) -> Result<Self> {
        let device = gpu.raw();
        let info =
            vk::BufferCreateInfo::default().size(size.max(4)).usage(usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info; the buffer is destroyed in Drop (or below on failure).
        let raw = unsafe { device.create_buffer(&info, None) }.during("vkCreateBuffer")?;
        gpu.device.set_name(raw, name);
        let mut dedicated = vk::MemoryDedicatedRequirements::default();
        let mut req2 = vk::MemoryRequirements2::default().push_next(&mut dedicated);
        // SAFETY: `raw` is a live buffer of this device.
        unsafe {
            device.get_buffer_memory_requirements2(&vk::BufferMemoryRequirementsInfo2::default().buffer(raw), &mut req2)
        };
        let req = req2.memory_requirements;
        let wants_own =
            dedicated.prefers_dedicated_allocation == vk::TRUE || dedicated.requires_dedicated_allocation == vk::TRUE;
        let own = wants_own.then(|| vk::MemoryDedicatedAllocateInfo::default().buffer(raw));
        let allocation = match gpu.allocator.borrow_mut().allocate(name, req, location, ResourceKind::Linear, own) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: never bound, never used.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        let buffer = Buffer { gpu, raw, size, allocation: Some(allocation) };
        let memory = buffer.allocation.as_ref().map(|a| (a.memory, a.offset)).expect("just placed");
        // SAFETY: the allocation satisfies `req` (type, size, alignment).
        unsafe { device.bind_buffer_memory(raw, memory.0, memory.1) }.during("vkBindBufferMemory")?;
        Ok(buffer)
    }

    /// Copies `data` to the start of a mapped buffer.
    pub fn write<T: Copy>(&self, data: &[T]) -> Result<()> {
        self.write_at(0, data)
    }

    /// Copies `data` to byte `offset` of a mapped buffer.
    pub fn write_at<T: Copy>(&self, offset: u64, data: &[T]) -> Result<()> {
        let allocation = self.allocation.as_ref().expect("live buffer");
        let bytes = std::mem::size_of_val(data);
        assert!(
            offset + bytes as u64 <= self.size,
            "write of {bytes} bytes at {offset} into a {}-byte buffer",
            self.size
        );
        let ptr = allocation.mapped().expect("write to an unmapped buffer");
        // SAFETY: the mapping covers [offset, offset + bytes) (asserted), and the GPU is not
        // reading that range (the fence of the frame that last used it was waited on).
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr() as *const u8, ptr.add(offset as usize), bytes) };
        self.gpu.allocator.borrow().flush(allocation)
    }

    /// Reads `count` values of T from the start of a mapped readback buffer.
    pub fn read<T: Pod>(&self, count: usize) -> Result<Vec<T>> {
        let allocation = self.allocation.as_ref().expect("live buffer");
        assert!((count * std::mem::size_of::<T>()) as u64 <= self.size);
        self.gpu.allocator.borrow().invalidate(allocation)?;
        let ptr = allocation.mapped().expect("read from an unmapped buffer");
        let mut out = vec![T::default(); count];
        // SAFETY: the mapping covers the bytes read; the GPU finished writing (fence waited).
        unsafe { std::ptr::copy_nonoverlapping(ptr, out.as_mut_ptr() as *mut u8, count * std::mem::size_of::<T>()) };
        Ok(out)
    }

    /// A view of the whole buffer as texels of `format` (`texel_bytes` each), for a texel-buffer
    /// binding: a shader's texelFetch reads it as the texture unit gathers, where a storage buffer's
    /// divergent reads are fetched lane by lane on some drivers (lavapipe). The buffer was made with
    /// the matching TEXEL_BUFFER usage; its texels must fit the device's maxTexelBufferElements.
    pub fn texel_view(&self, format: vk::Format, texel_bytes: u64, name: &str) -> Result<Owned<'g, vk::BufferView>> {
        let texels = self.size / texel_bytes;
        assert!(texels > 0, "a texel view of {name} needs a buffer of at least one {texel_bytes}-byte texel");
        let limit = u64::from(self.gpu.device.properties.limits.max_texel_buffer_elements);
        if texels > limit {
            return Err(Error::MissingFeature {
                device: self.gpu.device.name.clone(),
                feature: format!(
                    "room for {texels} texels in one texel buffer ({name}); its maxTexelBufferElements is {limit}"
                ),
            });
        }
        let info =
            vk::BufferViewCreateInfo::default().buffer(self.raw).format(format).offset(0).range(texels * texel_bytes);
        // SAFETY: a live buffer of this device, the range inside it and within the texel limit.
        let raw = unsafe { self.gpu.raw().create_buffer_view(&info, None) }.during("vkCreateBufferView")?;
        Ok(Owned::new(&self.gpu.device, raw, name))
    }

    /// Reads `pixels` RGBA16F texels (an image copied out) as f32.
    pub fn read_rgba16f(&self, pixels: usize) -> Result<Vec<[f32; 4]>> {
        let bits: Vec<u16> = self.read(4 * pixels)?;
        Ok(bits.chunks_exact(4).map(|p| std::array::from_fn(|c| half::f16::from_bits(p[c]).to_f32())).collect())
    }
}

impl Drop for Buffer<'_> {
    fn drop(&mut self) {
        // SAFETY: the device is idle (Renderer's Drop waits) or the buffer was never used.
        unsafe { self.gpu.raw().destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            self.gpu.allocator.borrow_mut().free(a);
        }
    }
}
