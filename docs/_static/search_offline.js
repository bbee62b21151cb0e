/* Search results with text on a site opened from disk (file://).
 *
 * Under each page it finds, Sphinx's search shows the lines around the words searched, which
 * it reads by fetching that page. A browser refuses fetch() on a page opened from disk, so
 * there every result would show its title only. search_pages.js, written at the end of the
 * build (docs/search_offline.py), holds each page's main content reduced to its text and its
 * anchors; on file:// a fetch() of a page of the site is answered from it. Served over http,
 * nothing changes.
 */
(() => {
  if (window.location.protocol !== "file:") return;
  const browserFetch = window.fetch.bind(window);
  window.fetch = (resource, options) => {
    const pages = window.RIGIDSIM_SEARCH_PAGES || {};
    const name = String(resource).replace(/^(\.\/)+/, "");
    if (!Object.hasOwn(pages, name)) return browserFetch(resource, options);
    const body = `<div role="main">${pages[name]}</div>`;
    const headers = { "Content-Type": "text/html; charset=utf-8" };
    return Promise.resolve(new Response(body, { headers }));
  };
})();
