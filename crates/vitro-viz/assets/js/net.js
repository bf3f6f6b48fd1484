// The WebSocket to the server: JSON messages in, commands out, reconnecting when dropped.

export class Connection {
  /** @param {(msg: object) => void} onMessage @param {(up: boolean) => void} onState */
  constructor(onMessage, onState) {
    this.onMessage = onMessage;
    this.onState = onState;
    this.ws = null;
    this.retry = 500;
    this.open();
  }

  open() {
    const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
    const ws = new WebSocket(`${proto}//${location.host}/ws`);
    this.ws = ws;
    ws.onopen = () => {
      this.retry = 500;
      this.onState(true);
    };
    ws.onmessage = (e) => {
      let msg;
      try {
        msg = JSON.parse(e.data);
      } catch (err) {
        console.warn('unreadable message', err);
        return;
      }
      this.onMessage(msg);
    };
    ws.onclose = () => {
      this.onState(false);
      setTimeout(() => this.open(), this.retry);
      this.retry = Math.min(this.retry * 2, 5000);
    };
  }

  /** Sends a command such as {cmd: 'step', n: 1}. */
  send(cmd) {
    if (this.ws && this.ws.readyState === WebSocket.OPEN) this.ws.send(JSON.stringify(cmd));
  }
}
