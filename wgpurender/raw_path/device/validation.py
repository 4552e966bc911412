"""The validation layer and a debug-utils messenger that collects what it says.

With $WGPURENDER_VALIDATION set (tests/conftest.py sets it), the instance enables
VK_LAYER_KHRONOS_validation, turns on synchronisation validation through
VkValidationFeaturesEXT (chained into VkInstanceCreateInfo.pNext), and installs a
VkDebugUtilsMessengerEXT whose callback appends every warning and error to a list.
A render that leaves anything in that list raises :class:`ValidationFailed`:
validation messages are bugs in this path, not noise.
"""

from __future__ import annotations

import os

import vulkan as vk

from wgpurender.core.errors import UserError

LAYER = "VK_LAYER_KHRONOS_validation"
ENV = "WGPURENDER_VALIDATION"
SEVERITIES = vk.VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | vk.VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT
TYPES = (
    vk.VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT
    | vk.VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT
    | vk.VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT
)


class ValidationFailed(RuntimeError):
    """The validation layer reported a message: a bug in the raw-Vulkan path."""


def validation_requested() -> bool:
    return os.environ.get(ENV, "") not in ("", "0")


def check_layer_available() -> None:
    names = {layer.layerName for layer in vk.vkEnumerateInstanceLayerProperties()}
    if LAYER not in names:
        raise UserError(f"${ENV} is set but {LAYER} is not installed "
                        f"(apt install vulkan-validationlayers, or unset ${ENV})")


def validation_features():
    """VkValidationFeaturesEXT that adds synchronisation validation (hazards between commands) to the default checks.

    The caller must keep the returned struct alive until vkCreateInstance returns.
    """
    return vk.VkValidationFeaturesEXT(
        pEnabledValidationFeatures=[vk.VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT],
    )


class MessageLog:
    """The messenger's callback target. The binding has one global callback slot, so one log per process."""

    def __init__(self) -> None:
        self.messages: list[str] = []

    def callback(self, severity, types, data, user_data) -> int:
        self.messages.append(vk.ffi.string(data.pMessage).decode(errors="replace"))
        return vk.VK_FALSE  # never abort the call that triggered the message

    def take(self) -> list[str]:
        messages, self.messages = self.messages, []
        return messages

    def raise_if_any(self, what: str) -> None:
        messages = self.take()
        if messages:
            raise ValidationFailed(f"{len(messages)} validation message(s) during {what}:\n" + "\n".join(messages[:5]))


def messenger_info(log: MessageLog):
    return vk.VkDebugUtilsMessengerCreateInfoEXT(
        messageSeverity=SEVERITIES, messageType=TYPES, pfnUserCallback=log.callback
    )


def create_messenger(instance, log: MessageLog):
    create = vk.vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT")
    return create(instance, messenger_info(log), None)


def destroy_messenger(instance, messenger) -> None:
    destroy = vk.vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT")
    destroy(instance, messenger, None)
