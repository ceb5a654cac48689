// Typed arrays from the base64 strings `sarmap view` writes into the page
// (tools/sarmap/view_data.cpp): raw little-endian values, as browsers on x86
// and ARM read them in place.

function bytesOf(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

export function uint8s(text) {
  return bytesOf(text);
}

export function float32s(text) {
  const bytes = bytesOf(text);
  return new Float32Array(bytes.buffer, 0, bytes.length / 4);
}

export function uint32s(text) {
  const bytes = bytesOf(text);
  return new Uint32Array(bytes.buffer, 0, bytes.length / 4);
}
