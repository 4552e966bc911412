"""The API-free course core: data both rendering paths read; it imports no GPU API and no path."""
