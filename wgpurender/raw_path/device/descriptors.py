"""Course concepts: descriptor set layouts, a descriptor pool, descriptor sets and vkUpdateDescriptorSets.

A VkDescriptorSetLayout lists a set's bindings (binding number, descriptor type,
count, shader stages that see it) and is what the pipeline layout is built from.
Descriptor sets are allocated from a VkDescriptorPool sized for the descriptor
types and set count it will hand out, then pointed at real resources (a buffer
range, an image view in a layout, a sampler) with vkUpdateDescriptorSets, and
bound in the command buffer with vkCmdBindDescriptorSets.
"""

from __future__ import annotations

from collections import Counter
from contextlib import ExitStack

import vulkan as vk

from wgpurender.raw_path.device.context import VulkanContext


def binding(index: int, kind: int, stages: int, count: int = 1):
    """VkDescriptorSetLayoutBinding: ``count`` descriptors of type ``kind`` at binding ``index``."""
    return vk.VkDescriptorSetLayoutBinding(binding=index, descriptorType=kind, descriptorCount=count, stageFlags=stages)


def create_set_layout(ctx: VulkanContext, owned: ExitStack, bindings: list):
    info = vk.VkDescriptorSetLayoutCreateInfo(pBindings=bindings)
    layout = vk.vkCreateDescriptorSetLayout(ctx.device, info, None)
    owned.callback(vk.vkDestroyDescriptorSetLayout, ctx.device, layout, None)
    return layout


def create_pool(ctx: VulkanContext, owned: ExitStack, layouts_bindings: list[list]):
    """A pool holding exactly the descriptors of the given sets (one list of bindings per set)."""
    counts = Counter()
    for bindings in layouts_bindings:
        for b in bindings:
            counts[b.descriptorType] += b.descriptorCount
    sizes = [vk.VkDescriptorPoolSize(type=kind, descriptorCount=n) for kind, n in sorted(counts.items())]
    info = vk.VkDescriptorPoolCreateInfo(maxSets=len(layouts_bindings), pPoolSizes=sizes)
    pool = vk.vkCreateDescriptorPool(ctx.device, info, None)
    owned.callback(vk.vkDestroyDescriptorPool, ctx.device, pool, None)  # frees its sets too
    return pool


def allocate_sets(ctx: VulkanContext, pool, layouts: list) -> list:
    info = vk.VkDescriptorSetAllocateInfo(descriptorPool=pool, pSetLayouts=layouts)
    return list(vk.vkAllocateDescriptorSets(ctx.device, info))


def write_buffer(dst_set, index: int, buffer, offset: int, size: int,
                 kind: int = vk.VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER) -> tuple:
    """A write pointing binding ``index`` at a buffer range; returns (write, info) to keep the info alive."""
    info = vk.VkDescriptorBufferInfo(buffer=buffer, offset=offset, range=size)
    write = vk.VkWriteDescriptorSet(dstSet=dst_set, dstBinding=index, dstArrayElement=0, descriptorCount=1,
                                    descriptorType=kind, pBufferInfo=[info])
    return write, info


def write_image(dst_set, index: int, view, layout: int, kind: int, sampler=None) -> tuple:
    """A write pointing binding ``index`` at an image view (plus a sampler for combined image samplers)."""
    info = vk.VkDescriptorImageInfo(sampler=sampler, imageView=view, imageLayout=layout)
    write = vk.VkWriteDescriptorSet(dstSet=dst_set, dstBinding=index, dstArrayElement=0, descriptorCount=1,
                                    descriptorType=kind, pImageInfo=[info])
    return write, info


def update(ctx: VulkanContext, writes: list[tuple]) -> None:
    """vkUpdateDescriptorSets with the writes (each a (write, info) pair from write_buffer / write_image)."""
    vk.vkUpdateDescriptorSets(ctx.device, len(writes), [w for w, _ in writes], 0, None)
