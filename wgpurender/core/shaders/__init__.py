"""The shader sources' files, their variants and the uniform layouts generated for them."""
