"""Vocabulary: frame and axis names, argument checks, and design constraints."""
