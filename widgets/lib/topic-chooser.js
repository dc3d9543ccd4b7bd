// The real-log panel's topic choice: a ROS 2 bag with several LaserScan or
// Odometry topics is refused until the reader names one of each, and the
// core's state then lists them (`state.topics`: `{ scanTopics, odomTopics
// }`, each `[{ topic, type, messages }]`). This offers them, each with its
// type and message count, and hands the pair chosen back to the panel,
// which opens the bag again with them (docs/ARCHITECTURE.md, "Pose sources
// and log formats": the reader of a format takes its topics before the
// first read).
import { el, select, button } from './ui.js';

const count = (n) => Number(n).toLocaleString('en-US');

/** How a topic reads in a menu: `/scan (sensor_msgs/msg/LaserScan, 1,234 messages)`. */
function topicLabel(t) {
  return `${t.topic} (${t.type}, ${count(t.messages)} ${t.messages === 1 ? 'message' : 'messages'})`;
}

/**
 * The chooser, hidden until `show(topics, onChoose)`; `onChoose({ scan,
 * odom })` gets the topics picked when the reader maps them. `hide()`
 * hides it again (and lets the bag's bytes go).
 */
export function topicChooser() {
  let chosen = null;
  const note = el('p', { class: 'occgrid-caption' });
  const scan = select('LaserScan topic', [], '', () => {}, { name: 'scan-topic' });
  const odom = select('Odometry topic', [], '', () => {}, { name: 'odom-topic' });
  const go = button('Map these topics', () => chosen?.({ scan: scan.input.value, odom: odom.input.value }), { name: 'map-topics' });
  const root = el('div', { class: 'map-weaver-log-topics occgrid-controls', role: 'group', 'aria-label': 'topics to map', hidden: true },
    note, scan.root, odom.root, go);
  const fill = (menu, topics) => {
    menu.input.replaceChildren(...topics.map((t) => el('option', { value: t.topic }, topicLabel(t))));
    menu.input.value = topics[0]?.topic ?? '';
  };
  return {
    root,
    show(topics, onChoose) {
      fill(scan, topics.scanTopics);
      fill(odom, topics.odomTopics);
      note.textContent = `This bag holds ${count(topics.scanTopics.length)} LaserScan and ${count(topics.odomTopics.length)} Odometry topics: choose the scans to map and the odometry that places them.`;
      chosen = onChoose;
      root.hidden = false;
    },
    hide() {
      chosen = null;
      root.hidden = true;
    },
  };
}
