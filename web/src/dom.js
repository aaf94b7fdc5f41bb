/*
 * dom.js — `$(id)`: an element of index.html by its id. The dashboard's
 * panels are fixed in index.html; each module looks up its own elements.
 */
export const $ = (id) => document.getElementById(id);
