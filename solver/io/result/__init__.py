"""Result files (JSON, compact, JSON lines): written, streamed, scanned and read back into typed frames."""
