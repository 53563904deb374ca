//! Placeholder: shared test helpers (scanner, namespace harness) land here.
