// SPDX-License-Identifier: MIT
// The program files a slice produces, by the result's programExtension: MIME type, what the page
// calls them, and the file name made from the model's. Shared by the page's download button and
// the embedding module.

/** Program kinds by file extension: download MIME type and the page's name for them. */
export const PROGRAM_KINDS = Object.freeze({
  gcode: Object.freeze({ mime: 'text/x-gcode', label: 'G-code' }),
  csv: Object.freeze({ mime: 'text/csv', label: 'robot CSV' }),
  script: Object.freeze({ mime: 'text/plain', label: 'URScript' }),
  mod: Object.freeze({ mime: 'text/plain', label: 'ABB RAPID module' }),
  src: Object.freeze({ mime: 'text/plain', label: 'KUKA KRL program' }),
});

/** The extension of a result's program: its programExtension when known, else 'gcode'. */
export function programExtension(extension) {
  return Object.hasOwn(PROGRAM_KINDS, extension) ? extension : 'gcode';
}

/**
 * Program file name for a model file name: ('part.stl') -> 'part.gcode'; with the result's
 * programExtension: ('part.stl', 'csv') -> 'part.csv', ('part.stl', 'script') -> 'part.script'.
 */
export function programFileName(modelName, extension = 'gcode') {
  const base = String(modelName || '').split(/[\\/]/).pop().replace(/\.[^.]*$/, '');
  return `${base || 'model'}.${programExtension(extension)}`;
}
