"""Helpers the tests share: independent physics, log and bag writers, the explorer under Pilot."""
