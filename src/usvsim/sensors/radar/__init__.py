"""X-band marine radar: beam rays, clutter, sectors, images, ARPA tracks."""
