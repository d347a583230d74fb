// Replaced by the render layer.
