//! Our device-memory sub-allocator: a few large blocks per memory type, first-fit placement with
//! alignment and bufferImageGranularity, free and reuse, named allocations and a leak report.

use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::collections::BTreeMap;

/// Size of a regular block. Requests over half of it, and those the driver wants dedicated, get a
/// block of their own of exactly their size (a frame's few large images and buffers), so that
/// reserved memory stays within a block of what is used.
pub const BLOCK_SIZE: u64 = 8 << 20;
const OWN_BLOCK_ABOVE: u64 = BLOCK_SIZE / 2;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// Device-local, not mapped.
    Gpu,
    /// Written by the CPU each frame, read by the GPU (uniforms, wave trains).
    Upload,
    /// Written by the GPU, read by the CPU (readback).
    Readback,
}

/// Linear resources (buffers) and optimal-tiling images must not share a bufferImageGranularity page.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResourceKind {
    Linear,
    Optimal,
}

#[derive(Debug)]
struct Placement {
    size: u64,
    kind: ResourceKind,
    name: String,
}

struct Block {
    raw: vk::DeviceMemory,
    size: u64,
    memory_type: u32,
    /// Holds one resource (dedicated, or larger than half a block): freed with it.
    own: bool,
    mapped: *mut u8,
    live: BTreeMap<u64, Placement>,
}

/// A live sub-allocation. Must be returned with `Allocator::free`.
#[derive(Debug)]
pub struct Allocation {
    pub memory: vk::DeviceMemory,
    pub offset: u64,
    pub size: u64,
    block: usize,
    mapped: *mut u8,
    coherent: bool,
}

impl Allocation {
    /// CPU pointer to this allocation, for mapped (Upload, Readback) locations.
    pub fn mapped(&self) -> Option<*mut u8> {
        (!self.mapped.is_null()).then_some(self.mapped)
    }
}

#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct MemoryReport {
    pub blocks: usize,
    pub reserved_bytes: u64,
    pub used_bytes: u64,
    pub device_local_reserved_bytes: u64,
    pub allocations: Vec<(String, u64)>,
}

pub struct Allocator {
    device: ash::Device,
    properties: vk::PhysicalDeviceMemoryProperties,
    granularity: u64,
    non_coherent_atom: u64,
    blocks: Vec<Option<Block>>,
}

fn align_up(value: u64, alignment: u64) -> u64 {
    value.div_ceil(alignment) * alignment
}

fn same_page(end_of_first: u64, start_of_second: u64, page: u64) -> bool {
    // The last byte of the first resource and the first byte of the second.
    (end_of_first - 1) / page == start_of_second / page
}

impl Allocator {
    pub fn new(
        device: ash::Device,
        properties: vk::PhysicalDeviceMemoryProperties,
        limits: &vk::PhysicalDeviceLimits,
    ) -> Allocator {
        Allocator {
            device,
            properties,
            granularity: limits.buffer_image_granularity.max(1),
            non_coherent_atom: limits.non_coherent_atom_size.max(1),
            blocks: Vec::new(),
        }
    }

    fn memory_type(&self, type_bits: u32, location: Location) -> Option<u32> {
        use vk::MemoryPropertyFlags as M;
        // Most preferred first; the last entry of each is the minimum acceptable.
        let preferences: &[M] = match location {
            Location::Gpu => &[M::DEVICE_LOCAL, M::empty()],
            Location::Upload => &[
                M::HOST_VISIBLE | M::HOST_COHERENT | M::DEVICE_LOCAL,
                M::HOST_VISIBLE | M::HOST_COHERENT,
                M::HOST_VISIBLE,
            ],
            Location::Readback => &[M::HOST_VISIBLE | M::HOST_CACHED, M::HOST_VISIBLE],
        };
        let types = &self.properties.memory_types[..self.properties.memory_type_count as usize];
        preferences.iter().find_map(|&want| {
            types
                .iter()
                .enumerate()
                .position(|(i, t)| type_bits & (1 << i) != 0 && t.property_flags.contains(want))
                .map(|i| i as u32)
        })
    }

    fn flags(&self, memory_type: u32) -> vk::MemoryPropertyFlags {
        self.properties.memory_types[memory_type as usize].property_flags
    }

    /// First fit in one block, honouring alignment and keeping resources of another kind off the
    /// same granularity page on both sides.
    fn fit(&self, block: &Block, size: u64, alignment: u64, kind: ResourceKind) -> Option<u64> {
        let page = self.granularity;
        let mut cursor = 0u64;
        let mut previous: Option<ResourceKind> = None;
        let mut gaps: Vec<(u64, u64, Option<ResourceKind>, Option<ResourceKind>)> = Vec::new();
        for (&offset, p) in &block.live {
            gaps.push((cursor, offset, previous, Some(p.kind)));
            cursor = offset + p.size;
            previous = Some(p.kind);
        }
        gaps.push((cursor, block.size, previous, None));
        gaps.into_iter().find_map(|(start, end, before, after)| {
            let mut offset = align_up(start, alignment);
            if before.is_some_and(|k| k != kind) && start > 0 && same_page(start, offset, page) {
                offset = align_up(offset, page);
            }
            let stop = offset.checked_add(size)?;
            if stop > end {
                return None;
            }
            if after.is_some_and(|k| k != kind) && end < block.size && same_page(stop, end, page) {
                return None;
            }
            Some(offset)
        })
    }

    /// Allocates `req` for a resource called `name`. `dedicated` asks for a block of its own.
    pub fn allocate(
        &mut self,
        name: &str,
        req: vk::MemoryRequirements,
        location: Location,
        kind: ResourceKind,
        dedicated: Option<vk::MemoryDedicatedAllocateInfo<'_>>,
    ) -> Result<Allocation> {
        let memory_type = self.memory_type(req.memory_type_bits, location).ok_or_else(|| Error::OutOfMemory {
            name: format!("{name}: no memory type for {location:?}"),
            bytes: req.size,
        })?;
        // Non-coherent host memory is flushed and invalidated in whole atoms: keep every
        // allocation on atom boundaries so that a flush never touches a neighbour's bytes.
        let flags = self.flags(memory_type);
        let non_coherent = flags.contains(vk::MemoryPropertyFlags::HOST_VISIBLE)
            && !flags.contains(vk::MemoryPropertyFlags::HOST_COHERENT);
        let alignment = if non_coherent { req.alignment.max(self.non_coherent_atom) } else { req.alignment.max(1) };
        let req = vk::MemoryRequirements {
            size: if non_coherent { align_up(req.size, self.non_coherent_atom) } else { req.size },
            ..req
        };
        let own_block = dedicated.is_some() || req.size > OWN_BLOCK_ABOVE;
        if !own_block {
            for (index, block) in self.blocks.iter().enumerate() {
                let Some(block) = block else { continue };
                if block.memory_type != memory_type || block.own {
                    continue;
                }
                if let Some(offset) = self.fit(block, req.size, alignment, kind) {
                    return Ok(self.place(index, offset, req.size, kind, name));
                }
            }
        }
        let size = if own_block { req.size } else { BLOCK_SIZE };
        let index = self.new_block(name, size, memory_type, dedicated, own_block)?;
        Ok(self.place(index, 0, req.size, kind, name))
    }

    fn new_block(
        &mut self,
        name: &str,
        size: u64,
        memory_type: u32,
        dedicated: Option<vk::MemoryDedicatedAllocateInfo<'_>>,
        own: bool,
    ) -> Result<usize> {
        let mut info = vk::MemoryAllocateInfo::default().allocation_size(size).memory_type_index(memory_type);
        let mut dedicated_info = dedicated;
        if let Some(d) = dedicated_info.as_mut() {
            info = info.push_next(d);
        }
        // SAFETY: the type index comes from this device's memory properties and `size` > 0.
        let raw = unsafe { self.device.allocate_memory(&info, None) }.map_err(|result| match result {
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
                Error::OutOfMemory { name: name.to_owned(), bytes: size }
            }
            result => Error::Vulkan { call: "vkAllocateMemory", result },
        })?;
        let mapped = if self.flags(memory_type).contains(vk::MemoryPropertyFlags::HOST_VISIBLE) {
            // SAFETY: host-visible memory mapped once, whole, for the block's lifetime.
            unsafe { self.device.map_memory(raw, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
                .during("vkMapMemory")? as *mut u8
        } else {
            std::ptr::null_mut()
        };
        let block = Block { raw, size, memory_type, own, mapped, live: BTreeMap::new() };
        if let Some(slot) = self.blocks.iter().position(Option::is_none) {
            self.blocks[slot] = Some(block);
            Ok(slot)
        } else {
            self.blocks.push(Some(block));
            Ok(self.blocks.len() - 1)
        }
    }

    fn place(&mut self, index: usize, offset: u64, size: u64, kind: ResourceKind, name: &str) -> Allocation {
        let coherent = {
            let block = self.blocks[index].as_ref().expect("placing into a live block");
            self.flags(block.memory_type).contains(vk::MemoryPropertyFlags::HOST_COHERENT)
        };
        let block = self.blocks[index].as_mut().expect("placing into a live block");
        block.live.insert(offset, Placement { size, kind, name: name.to_owned() });
        // SAFETY: offset + size lies inside the mapped block.
        let mapped = if block.mapped.is_null() { block.mapped } else { unsafe { block.mapped.add(offset as usize) } };
        Allocation { memory: block.raw, offset, size, block: index, mapped, coherent }
    }

    /// Returns an allocation. A block of its own goes back to the driver with it; an emptied
    /// shared block too, unless it is the last of its memory type (kept to avoid churn).
    pub fn free(&mut self, allocation: Allocation) {
        let Some(block) = self.blocks[allocation.block].as_mut() else {
            return;
        };
        block.live.remove(&allocation.offset);
        let (empty, own, memory_type) = (block.live.is_empty(), block.own, block.memory_type);
        let shared_of_type = self.blocks.iter().flatten().filter(|b| !b.own && b.memory_type == memory_type).count();
        if empty && (own || shared_of_type > 1) {
            let block = self.blocks[allocation.block].take().expect("checked above");
            // SAFETY: no live sub-allocation refers to this memory any more.
            unsafe { self.device.free_memory(block.raw, None) };
        }
    }

    /// The atom-aligned range of a non-coherent allocation (allocations there are atom-aligned, so
    /// it never reaches a neighbour); None for coherent memory, which needs no flush.
    fn non_coherent_range(&self, allocation: &Allocation) -> Option<vk::MappedMemoryRange<'static>> {
        if allocation.coherent {
            return None;
        }
        let atom = self.non_coherent_atom;
        let start = allocation.offset / atom * atom;
        let end = align_up(allocation.offset + allocation.size, atom);
        let block_size = self.blocks[allocation.block].as_ref().map_or(end, |b| b.size);
        Some(vk::MappedMemoryRange::default().memory(allocation.memory).offset(start).size(end.min(block_size) - start))
    }

    /// Makes GPU writes to a non-coherent readback allocation visible to the CPU.
    pub fn invalidate(&self, allocation: &Allocation) -> Result<()> {
        let Some(range) = self.non_coherent_range(allocation) else { return Ok(()) };
        // SAFETY: the range lies in a mapped block.
        unsafe { self.device.invalidate_mapped_memory_ranges(&[range]) }.during("vkInvalidateMappedMemoryRanges")
    }

    /// Makes CPU writes to a non-coherent upload allocation visible to the GPU.
    pub fn flush(&self, allocation: &Allocation) -> Result<()> {
        let Some(range) = self.non_coherent_range(allocation) else { return Ok(()) };
        // SAFETY: the range lies in a mapped block.
        unsafe { self.device.flush_mapped_memory_ranges(&[range]) }.during("vkFlushMappedMemoryRanges")
    }

    pub fn report(&self) -> MemoryReport {
        let mut r = MemoryReport::default();
        for block in self.blocks.iter().flatten() {
            r.blocks += 1;
            r.reserved_bytes += block.size;
            if self.flags(block.memory_type).contains(vk::MemoryPropertyFlags::DEVICE_LOCAL) {
                r.device_local_reserved_bytes += block.size;
            }
            for p in block.live.values() {
                r.used_bytes += p.size;
                r.allocations.push((p.name.clone(), p.size));
            }
        }
        r
    }

    /// Names of allocations still live (a leak if called at shutdown).
    pub fn live_allocations(&self) -> Vec<String> {
        self.blocks
            .iter()
            .flatten()
            .flat_map(|b| b.live.values().map(|p| format!("{} ({} bytes)", p.name, p.size)))
            .collect()
    }
}

impl Drop for Allocator {
    fn drop(&mut self) {
        let leaks = self.live_allocations();
        if !leaks.is_empty() {
            eprintln!("memory leak report: {} allocation(s) never freed: {}", leaks.len(), leaks.join(", "));
        }
        for block in self.blocks.drain(..).flatten() {
            // SAFETY: the owner waited for the device to idle before dropping the allocator.
            unsafe { self.device.free_memory(block.raw, None) };
        }
    }
}
