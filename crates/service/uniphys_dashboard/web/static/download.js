/**
 * Saving a file the browser cannot fetch by itself (every API call needs the auth header): the
 * bytes are fetched into a Blob, then handed to a temporary object URL link.
 */

import { getBlob } from './api.js';
import { h } from './dom.js';

/** Offers `blob` to the user as a download named `fileName`. */
export function saveBlob(blob, fileName) {
  const url = URL.createObjectURL(blob);
  const link = h('a', { href: url, download: fileName, hidden: true });
  document.body.append(link);
  link.click();
  link.remove();
  // The click starts the download asynchronously: keep the URL alive a little.
  setTimeout(() => URL.revokeObjectURL(url), 30_000);
}

/** Fetches `href` with the key and saves it as `fileName`. */
export async function downloadWithKey(href, fileName) {
  saveBlob(await getBlob(href), fileName);
}
