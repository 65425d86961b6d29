/**
 * Periodic refresh of a page's data: one run at a time (a tick that finds the previous run still
 * in flight is skipped), no runs while the tab is hidden, and everything stops with the page.
 */

/** Runs `task(signal)` now and every `intervalMs` until {@link Poller#stop}. */
export class Poller {
  /**
   * @param {(signal: AbortSignal) => Promise<void>} task fetches and renders; throws on failure.
   * @param {{intervalMs?: number, onChange?: () => void}} options `onChange` runs after each run.
   */
  constructor(task, { intervalMs = 2000, onChange = () => {} } = {}) {
    this.task = task;
    this.intervalMs = intervalMs;
    this.onChange = onChange;
    /** Unix ms of the last run that succeeded, or null. */
    this.lastSuccessMs = null;
    /** The last run's error, or null when it succeeded. */
    this.error = null;
    this.inFlight = false;
    this.stopped = true;
    this.again = false;
    this.controller = new AbortController();
    this.onVisible = () => {
      if (!document.hidden) this.tick();
    };
  }

  /** Runs the task now, then every interval. */
  start() {
    if (!this.stopped) return;
    this.stopped = false;
    this.timer = setInterval(() => this.tick(), this.intervalMs);
    document.addEventListener('visibilitychange', this.onVisible);
    this.tick();
  }

  /** Runs the task now, or as soon as the run in flight ends (after a user action). */
  refresh() {
    if (this.inFlight) this.again = true;
    else this.tick(true);
  }

  /** Stops the timer; a run in flight completes (a page whose data stopped changing). */
  pause() {
    this.stopped = true;
    clearInterval(this.timer);
    document.removeEventListener('visibilitychange', this.onVisible);
  }

  /** Stops the timer and aborts the run in flight; its result is dropped (leaving the page). */
  stop() {
    this.pause();
    this.controller.abort();
  }

  async tick(force = false) {
    if (this.inFlight || (this.stopped && !force) || document.hidden) return;
    if (this.controller.signal.aborted) return;
    this.inFlight = true;
    try {
      await this.task(this.controller.signal);
      this.lastSuccessMs = Date.now();
      this.error = null;
    } catch (e) {
      if (e.name === 'AbortError') return;
      this.error = e;
    } finally {
      this.inFlight = false;
    }
    this.onChange();
    if (this.again) {
      this.again = false;
      this.tick(true);
    }
  }
}
