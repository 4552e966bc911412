"""The raw path's post chain: per-pixel effects in a subpass, neighbourhood effects in their own passes."""
