/**
 * Keyset paging for long lists (100,000 assets are never fetched at once): each page is asked
 * for with the `before` cursor the previous page answered as `next`. The cursors walked through
 * are kept, so "Newer" goes back without the server having to page backwards.
 */

import { h } from './dom.js';

export class Pager {
  /** @param {() => void} onMove called after a move: load the page at {@link Pager#before}. */
  constructor(onMove) {
    this.cursors = [null];
    this.next = null;
    this.newer = h('button', { type: 'button', class: 'newer', text: '← Newer', disabled: true,
      onclick: () => this.move(() => this.cursors.pop()) });
    this.older = h('button', { type: 'button', class: 'older', text: 'Older →', disabled: true,
      onclick: () => this.move(() => this.cursors.push(this.next)) });
    this.label = h('span', { class: 'page-number' });
    this.element = h('nav', { class: 'pager', 'aria-label': 'Pages' }, this.newer, this.label, this.older);
    this.onMove = onMove;
  }

  /** The cursor of the page to load (null: the newest). */
  get before() {
    return this.cursors[this.cursors.length - 1];
  }

  /** Records the `next` cursor of the page just loaded (null on the last page). */
  loaded(next) {
    this.next = next ?? null;
    this.older.disabled = !this.next;
    this.newer.disabled = this.cursors.length === 1;
    this.label.textContent = `page ${this.cursors.length}`;
  }

  move(step) {
    this.newer.disabled = true;
    this.older.disabled = true;
    step();
    this.onMove();
  }
}
