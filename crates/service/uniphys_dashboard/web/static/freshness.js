/**
 * How fresh a polled page is: "updated 4 s ago", and a banner while refreshes fail (the last data
 * stays on screen). Ticks once a second, which also advances every `[data-since-ms]` element
 * under the page (the elapsed time of running work) without a request.
 */

import { h } from './dom.js';
import { ago, duration } from './format.js';

export class Freshness {
  /**
   * @param {import('./poller.js').Poller} poller whose state is shown.
   * @param {Element} root whose `[data-since-ms]` elements show the time elapsed since then.
   * @param {string} pausedText said after the time once the poller is paused.
   */
  constructor(poller, root, pausedText = 'not refreshing') {
    this.poller = poller;
    this.root = root;
    this.pausedText = pausedText;
    this.status = h('span', { class: 'updated', 'aria-live': 'off', text: 'loading…' });
    this.banner = h('div', { class: 'banner stale', role: 'alert', hidden: true });
    this.element = h('div', { class: 'freshness' }, this.status, this.banner);
    this.timer = setInterval(() => this.update(), 1000);
  }

  /** Redraws the status, the banner and the elapsed times. */
  update() {
    const now = Date.now();
    const { lastSuccessMs, error } = this.poller;
    const paused = this.poller.stopped ? ` (${this.pausedText})` : '';
    this.status.textContent = lastSuccessMs === null ? 'loading…' : `updated ${ago(lastSuccessMs, now)}${paused}`;
    this.banner.hidden = !error;
    if (error) {
      // Changed only with the error: an alert that changed every second would be read out so.
      const shown = lastSuccessMs === null ? 'nothing could be loaded yet' : 'the data shown is from the last refresh that worked';
      const text = `Refresh failed: ${error.message}. ${shown[0].toUpperCase()}${shown.slice(1)}; retrying.`;
      if (this.banner.textContent !== text) this.banner.textContent = text;
    }
    for (const el of this.root.querySelectorAll('[data-since-ms]')) {
      el.textContent = duration(now - Number(el.dataset.sinceMs));
    }
  }

  dispose() {
    clearInterval(this.timer);
  }
}
