"""Model files to meshes: the OBJ and glTF readers, glTF's accessors and rules, tangents, procedural meshes."""
